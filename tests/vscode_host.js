// A stand-in for VS Code, for tests/test_vscode.py: loads the extension (argv[2]) with
// the `vscode` module and the language client replaced by recorders, activates it with
// the settings of argv[3] (JSON), changes the robot, then the command, deactivates, and
// prints what the extension asked for, as JSON.
"use strict";

const Module = require("module");

const settings = JSON.parse(process.argv[3]);
const seen = { clients: [], errors: [] };
let onChange;

const vscode = {
    workspace: {
        getConfiguration: (section) => ({ get: (key) => settings[`${section}.${key}`] }),
        onDidChangeConfiguration: (listener) => {
            onChange = listener;
            return { dispose() {} };
        },
    },
    window: { showErrorMessage: (message) => seen.errors.push(message) },
};

class LanguageClient {
    constructor(id, name, serverOptions, clientOptions) {
        this.record = { id, serverOptions, clientOptions, started: false, stopped: false,
            notifications: [] };
        seen.clients.push(this.record);
    }

    async start() { this.record.started = true; }

    async stop() { this.record.stopped = true; }

    async dispose() { this.record.stopped = true; }

    async sendNotification(method, params) {
        this.record.notifications.push({ method, params });
    }
}

const load = Module._load;
Module._load = function (request, ...rest) {
    if (request === "vscode") {
        return vscode;
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

(async () => {
    const extension = require(process.argv[2]);
    await extension.activate({ subscriptions: [] });
    settings["gest.robot"] = "rhand-maestro";
    await onChange(changed("gest.robot"));
    settings["gest.server.command"] = ["/opt/venv/bin/gestc", "lsp"];
    await onChange(changed("gest.server.command"));
    await extension.deactivate();
    console.log(JSON.stringify(seen));
})();
