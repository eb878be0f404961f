// The IRL extension's client: starts `irlc lsp` (the language server of irlc, over stdio)
// for IRL programs and the data lists (.toml) next to them. Settings: irlc.server.command
// (default "irlc") and irlc.server.args (more arguments of `irlc lsp`).
"use strict";

const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const settings = vscode.workspace.getConfiguration("irlc.server");
  const serverOptions = {
    command: settings.get("command", "irlc"),
    args: ["lsp", ...settings.get("args", [])],
    transport: TransportKind.stdio,
  };
  const clientOptions = {
    documentSelector: [
      { scheme: "file", language: "irl" },
      { scheme: "untitled", language: "irl" },
      { scheme: "file", pattern: "**/*.toml" }, // data lists: checked when a program imports them
    ],
  };
  client = new LanguageClient("irlc", "irlc language server", serverOptions, clientOptions);
  context.subscriptions.push({ dispose: () => client && client.stop() });
  return client.start().catch((error) => {
    vscode.window.showErrorMessage(
      `irlc lsp could not start (${error.message || error}). Install it with ` +
        `pip install 'irlc[lsp]' and set irlc.server.command to its irlc if it is not on PATH.`
    );
  });
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
