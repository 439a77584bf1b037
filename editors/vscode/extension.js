// The .gest language's client: starts the language server (`gestc lsp`, or the command
// of the gest.server.command setting) on standard input and output for gest files, and
// tells it the gest.robot setting: as initializationOptions when it starts, then in a
// workspace/didChangeConfiguration notification whenever the setting changes.
"use strict";

const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

const SECTION = "gest";
const INSTALL = "python -m pip install 'inmoov-dsl[lsp]'";

let client;

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
    } else if (event.affectsConfiguration(`${SECTION}.robot`) && client) {
        const { robot } = settings();
        await client.sendNotification("workspace/didChangeConfiguration",
            { settings: { [SECTION]: { robot } } });
    }
}

function activate(context) {
    context.subscriptions.push(vscode.workspace.onDidChangeConfiguration(changed));
    return start();
}

function deactivate() {
    return stop();
}

module.exports = { activate, deactivate };
