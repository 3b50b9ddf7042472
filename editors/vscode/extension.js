// A minimal VS Code client for `mapc lsp`: starts the server over stdio for map files.
// Build: `npm install && npx @vscode/vsce package`, then install the .vsix (docs/editors.md).
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

function activate() {
  const cfg = vscode.workspace.getConfiguration('mapc');
  const server = { command: cfg.get('path', 'mapc'), args: ['lsp', ...cfg.get('args', [])] };
  client = new LanguageClient('mapc', 'mapc', server, {
    documentSelector: [
      { scheme: 'file', pattern: '**/*.building.yaml' },
      { scheme: 'file', pattern: '**/*.project.yaml' },
      { scheme: 'file', pattern: '**/*.site.json' },
      { scheme: 'file', pattern: '**/*.scenario.yaml' },
    ],
  });
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
