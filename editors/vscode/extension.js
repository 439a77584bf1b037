// The .gest language's client: starts the language server (`gestc lsp`, or the command
// of the gest.server.command setting) on standard input and output for gest files, and
// tells it the gest.robot setting: as initializationOptions when it starts, then in a
// workspace/didChangeConfiguration notification whenever the setting changes.
//
// The preview: "Gest: Open Preview to the Side" (gest.openPreviewToSide) asks the server
// for the page of a document (workspace/executeCommand gest.preview [uri, {open: false}],
// answered {url}) and shows it in a webview panel beside the editor, one panel per
// document; the cursor of every gest editor is told to the server (gest/cursor), which
// marks the step under it on the page. A click on a step of the page comes back as
// window/showDocument, which the language client handles; the middleware below only
// picks the column: the one the document is shown in, not the preview's.
"use strict";

const crypto = require("crypto");
const path = require("path");
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

const SECTION = "gest";
const INSTALL = "python -m pip install 'inmoov-dsl[lsp]'";
const PREVIEW_COMMAND = "gest.openPreviewToSide";  // the editor's command
const SERVER_PREVIEW = "gest.preview";  // the server's command: the page's URL
const CURSOR = "gest/cursor";  // the notification of where the cursor is
const CURSOR_DELAY = 50;  // ms: the cursor is told once it has stopped this long
const VIEW_TYPE = "gest.previewPanel";  // the panels' kind (not the server's command)

let client;
/** The open previews, by their document's URI: { panel, url, column, document }: the
 * panel, the page it shows, the column its document was in, the document. */
const previews = new Map();
let cursorTimer;

/** The settings the server needs: its command, and the robot of files without one. */
function settings() {
    const config = vscode.workspace.getConfiguration(SECTION);
    return { command: config.get("server.command"), robot: config.get("robot") || "" };
}

/** Start the server for gest files (nothing if the command setting is not a command). */
async function start() {
    const { command, robot } = settings();
    if (!Array.isArray(command) || command.length === 0 || !command.every(
        (part) => typeof part === "string") || command[0] === "") {
        vscode.window.showErrorMessage(
            "Gest: gest.server.command must be a list of strings, the command first: " +
            "[\"gestc\", \"lsp\"]");
        return;
    }
    // no transport: the command is started as it is, on stdio (a transport would add
    // --stdio to its arguments)
    const serverOptions = { command: command[0], args: command.slice(1) };
    const clientOptions = {
        documentSelector: [
            { scheme: "file", language: "gest" },
            { scheme: "untitled", language: "gest" },
        ],
        initializationOptions: { robot },
        middleware: { window: { showDocument } },
    };
    client = new LanguageClient("gest", "Gest (gestc lsp)", serverOptions, clientOptions);
    try {
        await client.start();
    } catch (error) {
        const failed = client;
        client = undefined;
        failed.dispose().catch(() => undefined);
        vscode.window.showErrorMessage(
            `Gest: the language server '${command.join(" ")}' did not start ` +
            `(${error && error.message ? error.message : error}). Install it with ` +
            `${INSTALL}, or set gest.server.command.`);
    }
}

/** Stop the server, if one runs. */
async function stop() {
    const running = client;
    client = undefined;
    if (running) {
        await running.stop();
    }
}

/** A changed setting: a new command restarts the server, a new robot is told to it. */
async function changed(event) {
    if (event.affectsConfiguration(`${SECTION}.server.command`)) {
        await stop();
        await start();
        await reloadPreviews();
    } else if (event.affectsConfiguration(`${SECTION}.robot`) && client) {
        const { robot } = settings();
        await client.sendNotification("workspace/didChangeConfiguration",
            { settings: { [SECTION]: { robot } } });
    }
}

/** What an error says. */
function why(error) {
    return error && error.message ? error.message : String(error);
}

/** The URL of the server's page for ``document``; an error unless it is a page of
 * this computer (http://127.0.0.1:PORT/...). */
async function previewUrl(document) {
    if (!client) {
        throw new Error("the language server is not running");
    }
    const answer = await client.sendRequest("workspace/executeCommand", {
        command: SERVER_PREVIEW,
        arguments: [client.code2ProtocolConverter.asUri(document.uri), { open: false }],
    });
    let url;
    try {
        url = new URL(answer && answer.url);
    } catch (error) {
        throw new Error(`the server answered no URL: ${JSON.stringify(answer)}`);
    }
    if (url.protocol !== "http:" || url.hostname !== "127.0.0.1") {
        throw new Error(`the server's page is not on http://127.0.0.1: ${url.href}`);
    }
    return url.href;
}

/** ``text`` as it may stand in an HTML attribute. */
function escaped(text) {
    return text.replace(/&/g, "&amp;").replace(/"/g, "&quot;").replace(/</g, "&lt;")
        .replace(/>/g, "&gt;");
}

/** The webview's page: the server's page (``url``) filling it, in an iframe; its
 * Content-Security-Policy lets in frames of this computer's pages and nothing else
 * (no script of its own, no remote anything; its one style by a nonce). */
function previewHtml(url, name) {
    const nonce = crypto.randomBytes(16).toString("base64");
    const csp = `default-src 'none'; frame-src http://127.0.0.1:*; style-src 'nonce-${nonce}'`;
    return `<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="${csp}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<style nonce="${nonce}">
html, body { margin: 0; padding: 0; width: 100%; height: 100%; overflow: hidden; }
iframe { display: block; border: 0; width: 100%; height: 100%; }
</style>
</head>
<body>
<iframe src="${escaped(url)}" title="${escaped(`Preview of ${name}`)}"></iframe>
</body>
</html>
`;
}

/** The name a document's preview is titled with. */
function fileName(document) {
    return path.basename(document.uri.path || document.fileName || "") || document.fileName;
}

/** Show ``url`` in ``preview``'s panel (again only when it changed: that reloads it). */
function showUrl(preview, url, document) {
    if (preview.url !== url) {
        preview.url = url;
        preview.panel.webview.html = previewHtml(url, fileName(document));
    }
}

/** A panel beside ``column`` for ``document``, kept in ``previews`` until it closes. */
function createPreview(document, column) {
    const key = document.uri.toString();
    const panel = vscode.window.createWebviewPanel(
        VIEW_TYPE, `Preview: ${fileName(document)}`,
        { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
        // the page is a program (the 3-D view, its timeline): scripts run in its frame;
        // kept while hidden, so it does not start again each time it is shown
        { enableScripts: true, retainContextWhenHidden: true });
    const preview = { panel, url: undefined, column, document };
    previews.set(key, preview);
    panel.onDidDispose(() => {
        if (previews.get(key) === preview) {
            previews.delete(key);
        }
    });
    return preview;
}

/** The editor (and document) the command is for: the one of ``resource`` (the editor's
 * title bar gives it), else the active one. */
function target(resource) {
    const active = vscode.window.activeTextEditor;
    if (resource && resource.toString) {
        const uri = resource.toString();
        const editor = (active && active.document.uri.toString() === uri) ? active
            : vscode.window.visibleTextEditors.find((e) => e.document.uri.toString() === uri);
        const document = editor ? editor.document
            : vscode.workspace.textDocuments.find((d) => d.uri.toString() === uri);
        return { editor, document };
    }
    return { editor: active, document: active && active.document };
}

/** gest.openPreviewToSide: the document's preview beside it, made or shown again. */
async function openPreviewToSide(resource) {
    const { editor, document } = target(resource);
    if (!document || document.languageId !== "gest") {
        vscode.window.showErrorMessage("Gest: the preview is of a .gest file: open one first.");
        return;
    }
    const key = document.uri.toString();
    const open = previews.get(key);
    if (open) {
        open.panel.reveal(open.panel.viewColumn, true);
    }
    let url;
    try {
        url = await previewUrl(document);
    } catch (error) {
        vscode.window.showErrorMessage(`Gest: no preview (${why(error)}).`);
        return;
    }
    const preview = previews.get(key) ||
        createPreview(document, editor && editor.viewColumn);
    showUrl(preview, url, document);
    if (editor) {
        await sendCursor(editor);
    }
}

/** Every open preview asks the (new) server for its page again. */
async function reloadPreviews() {
    await Promise.all([...previews.values()].map(async (preview) => {
        try {
            const url = await previewUrl(preview.document);
            preview.url = undefined;  // the same URL too: its page is the new server's
            showUrl(preview, url, preview.document);
        } catch (error) {
            // the server did not start: it said so; the panel stays as it was
        }
    }));
}

/** Tell the server where ``editor``'s cursor is, when it shows a gest file. */
async function sendCursor(editor) {
    if (!client || !editor || editor.document.languageId !== "gest") {
        return;
    }
    const { line, character } = editor.selection.active;
    try {
        await client.sendNotification(CURSOR, {
            textDocument: { uri: client.code2ProtocolConverter.asUri(editor.document.uri) },
            position: { line, character },
        });
    } catch (error) {
        // the server stopped: nothing to tell
    }
}

/** The cursor moved in ``editor``: told once it stops (CURSOR_DELAY). */
function cursorMoved(editor) {
    if (!editor || editor.document.languageId !== "gest") {
        return;
    }
    clearTimeout(cursorTimer);
    cursorTimer = setTimeout(() => {
        cursorTimer = undefined;
        sendCursor(editor);
    }, CURSOR_DELAY);
}

/** window/showDocument from the server (a click on the page): in the column that shows
 * the document already, or, when the preview is where the click came from, in the column
 * its document was shown in; not over the preview (the language client would open it in
 * the active column: the preview's). A page to open in the browser is the client's. */
async function showDocument(params, next) {
    if (params.external === true || !client) {
        return next(params);
    }
    const uri = client.protocol2CodeConverter.asUri(params.uri);
    const shown = vscode.window.visibleTextEditors.find(
        (e) => e.document.uri.toString() === uri.toString());
    const active = [...previews.values()].find((p) => p.panel.active);
    const column = shown ? shown.viewColumn : active && active.column;
    if (column === undefined) {
        return next(params);
    }
    const options = { viewColumn: column, preserveFocus: params.takeFocus !== true };
    if (params.selection !== undefined) {
        options.selection = client.protocol2CodeConverter.asRange(params.selection);
    }
    try {
        await vscode.window.showTextDocument(uri, options);
        return { success: true };
    } catch (error) {
        return { success: false };
    }
}

function activate(context) {
    context.subscriptions.push(
        vscode.workspace.onDidChangeConfiguration(changed),
        vscode.commands.registerCommand(PREVIEW_COMMAND, openPreviewToSide),
        vscode.window.onDidChangeTextEditorSelection((event) => cursorMoved(event.textEditor)),
        vscode.window.onDidChangeActiveTextEditor(cursorMoved),
        { dispose: closePreviews });
    return start();
}

/** Close every preview, and forget the cursor not yet told. */
function closePreviews() {
    clearTimeout(cursorTimer);
    cursorTimer = undefined;
    for (const preview of [...previews.values()]) {
        preview.panel.dispose();
    }
    previews.clear();
}

function deactivate() {
    closePreviews();
    return stop();
}

module.exports = { activate, deactivate };
