// A stand-in for VS Code, for tests/test_vscode.py: loads the extension (argv[2]) with
// the `vscode` module and the language client replaced by recorders, activates it with
// the settings of argv[3] (JSON), plays the scenario argv[4] names, deactivates it, and
// prints what the extension asked for, as JSON.
//
// - "settings" (the default): changes the robot, then the command.
// - "preview": opens previews (gest.openPreviewToSide) and moves cursors; the server's
//   answer to gest.preview is http://127.0.0.1:(8000 + the client's number)/preview, an
//   error for a document whose name has "broken" in it.
// - "live": the extension (the packaged bundle, with the real language client in it)
//   talks to the server of its command setting (the stand-in of tests/test_neovim.py,
//   which writes what it reads to the file argv[5]) about the gesture file argv[6]: the
//   preview opened, the cursor moved, a click on the page played (its command
//   test.click). Here the stand-in for VS Code has what the language client uses too.
"use strict";

const fs = require("fs");
const Module = require("module");

const settings = JSON.parse(process.argv[3]);
const scenario = process.argv[4] || "settings";
const seen = { clients: [], errors: [], commands: [], panels: [], shown: [], next: [] };
let onChange;
const listeners = { selection: [], active: [] };
const registered = new Map();
const clients = [];

class Uri {
    constructor(text) {
        const url = new URL(text);
        this.scheme = url.protocol.slice(0, -1);
        this.path = decodeURIComponent(url.pathname);
        this.text = text;
    }

    static parse(text) { return new Uri(text); }

    toString() { return this.text; }

    toJSON() { return this.text; }
}

const ViewColumn = { Active: -1, Beside: -2, One: 1, Two: 2, Three: 3 };

/** A document: its URI and language; an editor: a document, its cursor, its column. */
function documentOf(uri, languageId) {
    return { uri: Uri.parse(uri), languageId, fileName: Uri.parse(uri).path };
}

function editorOf(document, line, character, viewColumn = ViewColumn.One) {
    return { document, viewColumn, selection: { active: { line, character } } };
}

const madePanels = [];  // the panels made, in order

/** A webview panel that records what is done to it. */
function panelOf(viewType, title, showOptions, options) {
    const record = { viewType, title, showOptions, options, htmls: [], reveals: [],
        disposed: false };
    seen.panels.push(record);
    const disposers = [];
    const panel = {
        viewType,
        title,
        active: false,
        viewColumn: ViewColumn.Two,
        record,
        webview: {
            set html(text) { record.htmls.push(text); },
            get html() { return record.htmls[record.htmls.length - 1]; },
        },
        reveal(column, preserveFocus) { record.reveals.push({ column, preserveFocus }); },
        onDidDispose(listener) {
            disposers.push(listener);
            return { dispose() {} };
        },
        dispose() {
            if (!record.disposed) {
                record.disposed = true;
                disposers.forEach((listener) => listener());
            }
        },
    };
    madePanels.push(panel);
    return panel;
}

const window = {
    activeTextEditor: undefined,
    visibleTextEditors: [],
    showErrorMessage: (message) => seen.errors.push(message),
    createWebviewPanel: panelOf,
    showTextDocument: async (uri, options) => {
        seen.shown.push({ uri: uri.toString(), options });
        return editorOf(documentOf(uri.toString(), "gest"), 0, 0, options.viewColumn);
    },
    onDidChangeTextEditorSelection: (listener) => {
        listeners.selection.push(listener);
        return { dispose() {} };
    },
    onDidChangeActiveTextEditor: (listener) => {
        listeners.active.push(listener);
        return { dispose() {} };
    },
};

const vscode = {
    Uri,
    ViewColumn,
    window,
    workspace: {
        textDocuments: [],
        getConfiguration: (section) => ({ get: (key) => settings[`${section}.${key}`] }),
        onDidChangeConfiguration: (listener) => {
            onChange = listener;
            return { dispose() {} };
        },
    },
    commands: {
        registerCommand: (id, callback) => {
            registered.set(id, callback);
            seen.commands.push(id);
            return { dispose() { registered.delete(id); } };
        },
        executeCommand: async (id, ...args) => registered.get(id)(...args),
    },
};

class LanguageClient {
    constructor(id, name, serverOptions, clientOptions) {
        this.record = { id, serverOptions, clientOptions, started: false, stopped: false,
            notifications: [], requests: [] };
        this.clientOptions = clientOptions;
        this.port = 8000 + clients.length;
        this.code2ProtocolConverter = { asUri: (uri) => uri.toString() };
        this.protocol2CodeConverter = {
            asUri: (text) => Uri.parse(text),
            asRange: (range) => ({ converted: range }),
        };
        seen.clients.push(this.record);
        clients.push(this);
    }

    async start() { this.record.started = true; }

    async stop() { this.record.stopped = true; }

    async dispose() { this.record.stopped = true; }

    async sendNotification(method, params) {
        this.record.notifications.push({ method, params });
    }

    async sendRequest(method, params) {
        this.record.requests.push({ method, params });
        if (method === "workspace/executeCommand" && params.command === "gest.preview") {
            if (params.arguments[0].includes("broken")) {
                throw new Error("no page for you");
            }
            return { url: `http://127.0.0.1:${this.port}/preview` };
        }
        throw new Error(`unknown request ${method}`);
    }
}

/** What the language client itself uses of VS Code's API (the "live" scenario). */
class EventEmitter {
    constructor() {
        this.listeners = new Set();
        this.event = (listener, thisArg) => {
            const bound = thisArg ? listener.bind(thisArg) : listener;
            this.listeners.add(bound);
            return { dispose: () => this.listeners.delete(bound) };
        };
    }

    fire(value) { [...this.listeners].forEach((listener) => listener(value)); }

    dispose() { this.listeners.clear(); }
}

class Disposable {
    constructor(dispose) { this.dispose = dispose || (() => undefined); }

    static from(...disposables) {
        return new Disposable(() => disposables.forEach((d) => d && d.dispose && d.dispose()));
    }
}

class Position {
    constructor(line, character) { Object.assign(this, { line, character }); }
}

class Range {
    constructor(...args) {
        const [start, end] = args.length === 4
            ? [new Position(args[0], args[1]), new Position(args[2], args[3])] : args;
        Object.assign(this, { start, end });
    }
}

Uri.file = (fsPath) => Uri.parse(`file://${fsPath.split("/").map(encodeURIComponent).join("/")}`);

/** Anything else the client asks of the stand-in: a callable that gives more of itself
 * (not a promise, not iterable but empty). */
function anything() {
    return new Proxy(function () {}, {
        get: (target, key) => {
            if (key === "then") {
                return undefined;
            }
            if (key === Symbol.iterator) {
                return function* () {};
            }
            if (key === Symbol.toPrimitive) {
                return () => "";
            }
            return key in target ? target[key] : (target[key] = anything());
        },
        apply: () => anything(),
        construct: () => anything(),
    });
}

/** ``members``, and anything() for what it does not have. */
function namespace(members) {
    return new Proxy(members, {
        get: (target, key) => (key in target ? target[key] : (target[key] = anything())),
    });
}

/** The stand-in as the language client needs it. */
function live() {
    const subscribe = () => new Disposable();
    Object.assign(vscode, { EventEmitter, Disposable, Position, Range, version: "1.82.0",
        env: namespace({ language: "en", appName: "stand-in", openExternal: async () => true }),
        languages: namespace({
            match: (selector, document) => ([].concat(selector).some((filter) =>
                (typeof filter === "string" ? filter : filter.language) === document.languageId &&
                (!filter.scheme || filter.scheme === document.uri.scheme)) ? 10 : 0),
            createDiagnosticCollection: () => anything(),
        }) });
    for (const name of ["onDidOpenTextDocument", "onDidCloseTextDocument",
        "onDidChangeTextDocument", "onWillSaveTextDocument", "onDidSaveTextDocument",
        "onDidChangeWorkspaceFolders"]) {
        vscode.workspace[name] = subscribe;
    }
    vscode.workspace.workspaceFolders = undefined;
    vscode.window = namespace(vscode.window);
    vscode.workspace = namespace(vscode.workspace);
    return namespace(vscode);
}

const load = Module._load;
const host = scenario === "live" ? live() : vscode;
Module._load = function (request, ...rest) {
    if (request === "vscode") {
        return host;
    }
    if (request === "vscode-languageclient/node") {
        return { LanguageClient };
    }
    return load.call(this, request, ...rest);
};

/** A configuration change event for the one setting ``key``. */
function changed(key) {
    return { affectsConfiguration: (section) => section === key || key.startsWith(`${section}.`) };
}

/** Wait until ``done()`` (polled), for at most a minute. */
async function until(done, what) {
    const deadline = Date.now() + 60000;
    while (!done()) {
        if (Date.now() > deadline) {
            throw new Error(`waited a minute for ${what}`);
        }
        await new Promise((resolve) => setTimeout(resolve, 10));
    }
}

/** The cursor of ``editor`` moved to ``line``, ``character``. */
function move(editor, line, character) {
    editor.selection = { active: { line, character } };
    listeners.selection.forEach((listener) => listener({ textEditor: editor }));
}

async function settingsScenario() {
    settings["gest.robot"] = "rhand-maestro";
    await onChange(changed("gest.robot"));
    settings["gest.server.command"] = ["/opt/venv/bin/gestc", "lsp"];
    await onChange(changed("gest.server.command"));
}

async function previewScenario() {
    const open = () => vscode.commands.executeCommand("gest.openPreviewToSide");
    const hand = documentOf("file:///work/hand.gest", "gest");
    const other = documentOf("file:///work/other%20hand.gest", "gest");
    const broken = documentOf("file:///work/broken.gest", "gest");
    const readme = documentOf("file:///work/README.md", "markdown");
    vscode.workspace.textDocuments.push(hand, other, broken, readme);
    const editor = editorOf(hand, 2, 4);
    window.activeTextEditor = editor;
    window.visibleTextEditors = [editor];
    seen.steps = {};
    const mark = (name) => {
        seen.steps[name] = { panels: seen.panels.length,
            notifications: clients[0].record.notifications.length,
            requests: clients[0].record.requests.length };
    };
    await open();  // a panel beside, the cursor told
    mark("opened");
    await open();  // the same panel, shown again
    mark("again");
    // cursors moving: a markdown file's is not told, a gest file's is once it stops
    move(editorOf(readme, 7, 7), 7, 7);
    move(editor, 3, 0);
    move(editor, 4, 2);
    move(editor, 5, 1);
    const told = (line, character) => clients[0].record.notifications.some((n) =>
        n.method === "gest/cursor" && n.params.position.line === line &&
        n.params.position.character === character);
    await until(() => told(5, 1), "the cursor at 5:1");
    mark("moved");
    // the active editor changes to another gest file: its cursor is told
    const otherEditor = editorOf(other, 9, 3, ViewColumn.Three);
    listeners.active.forEach((listener) => listener(otherEditor));
    await until(() => told(9, 3), "the cursor at 9:3");
    // a click on the page: window/showDocument through the middleware
    const { showDocument } = clients[0].clientOptions.middleware.window;
    const next = async (params) => {
        seen.next.push(params);
        return { success: true };
    };
    const selection = { start: { line: 1, character: 4 }, end: { line: 1, character: 9 } };
    const firstPanel = madePanels[0];
    firstPanel.active = true;
    seen.clicks = [
        // shown in an editor: in its column
        await showDocument({ uri: hand.uri.toString(), selection, takeFocus: true }, next),
        // shown in no editor, the preview active: in its document's column
        await showDocument({ uri: "file:///work/third.gest", selection }, next),
        // a page for the browser: the client's own
        await showDocument({ uri: "http://127.0.0.1:8000/", external: true }, next),
    ];
    firstPanel.active = false;
    // not shown, no preview active: the client's own
    seen.clicks.push(await showDocument({ uri: "file:///work/third.gest", selection }, next));
    // the panel closed, then opened again: a new one
    firstPanel.dispose();
    await open();
    mark("reopened");
    // from the title bar of another document's editor (its URI given): its own panel
    await vscode.commands.executeCommand("gest.openPreviewToSide", other.uri);
    // a document the server has no page for; a file that is no gesture file
    window.activeTextEditor = editorOf(broken, 0, 0);
    await open();
    window.activeTextEditor = editorOf(readme, 0, 0);
    await open();
    mark("refused");
    // a new server command: the open previews ask the new server for their pages
    settings["gest.server.command"] = ["/opt/venv/bin/gestc", "lsp"];
    await onChange(changed("gest.server.command"));
}

/** The server's log: what it read so far. */
function received() {
    return fs.readFileSync(process.argv[5], "utf-8").split("\n").filter(Boolean)
        .map((line) => JSON.parse(line));
}

/** The gesture file, open in the active editor, before the extension starts. */
function liveSetup() {
    const file = process.argv[6];
    const text = fs.readFileSync(file, "utf-8");
    const document = { ...documentOf(Uri.file(file).toString(), "gest"), version: 1,
        getText: () => text, isClosed: false, isUntitled: false };
    vscode.workspace.textDocuments.push(document);
    const editor = editorOf(document, 0, 0);
    window.activeTextEditor = editor;
    window.visibleTextEditors = [editor];
    return editor;
}

async function liveScenario(editor) {
    const uri = editor.document.uri.toString();
    await until(() => received().some((m) => m.method === "textDocument/didOpen"),
        "the document opened");
    await vscode.commands.executeCommand("gest.openPreviewToSide");
    move(editor, 1, 3);
    await until(() => received().some((m) => m.method === "gest/cursor" &&
        m.params.position.line === 1 && m.params.position.character === 3), "the cursor");
    // the language client made the server's commands VS Code's: a click on the page
    const range = { start: { line: 2, character: 1 }, end: { line: 2, character: 4 } };
    await vscode.commands.executeCommand("test.click", uri, range);
    await until(() => seen.shown.length > 0, "the click's place shown");
    await until(() => received().some((m) => m.id === "click-1" && m.result),
        "the click answered");
}

(async () => {
    const editor = scenario === "live" ? liveSetup() : undefined;
    const extension = require(process.argv[2]);
    await extension.activate({ subscriptions: [] });
    await ({ preview: previewScenario, live: liveScenario }[scenario] || settingsScenario)(editor);
    await extension.deactivate();
    console.log(JSON.stringify(seen));
})().catch((error) => {
    console.error(error);
    process.exit(1);
});
