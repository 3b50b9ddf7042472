// Run by tests/editor_setups.rs inside a real VS Code (code-server) next to the mapc
// extension of editors/vscode: opens m.building.yaml of the workspace as a user would,
// waits for the diagnostics that mapc's extension publishes, asks for a vertex's definition
// (as F12 does), deletes the self-loop lane (VS Code sends the change to the server) and
// waits for the diagnostics to update. Writes what it
// saw to diagnostics.txt in the workspace, then done.txt.
const vscode = require('vscode');
const fs = require('fs');
const path = require('path');

const sev = { 0: 'error', 1: 'warning', 2: 'info', 3: 'hint' };

function lines(tag, uri) {
  return vscode.languages
    .getDiagnostics(uri)
    .filter((d) => d.source === 'mapc')
    .map((d) => {
      const code = typeof d.code === 'object' ? d.code.value : d.code;
      return `${tag} ${d.range.start.line + 1}:${d.range.start.character + 1} ${code} ${sev[d.severity]}`;
    })
    .sort();
}

// Resolves when `pred()` holds after a diagnostics change for `uri`, or after 20 s.
function waitFor(uri, pred) {
  return new Promise((resolve) => {
    if (pred()) return resolve(true);
    const timer = setTimeout(() => { sub.dispose(); resolve(false); }, 20000);
    const sub = vscode.languages.onDidChangeDiagnostics((e) => {
      if (e.uris.some((u) => u.toString() === uri.toString()) && pred()) {
        clearTimeout(timer);
        sub.dispose();
        resolve(true);
      }
    });
  });
}

async function activate() {
  const dir = vscode.workspace.workspaceFolders[0].uri.fsPath;
  const out = [];
  try {
    const uri = vscode.Uri.file(path.join(dir, 'm.building.yaml'));
    const doc = await vscode.workspace.openTextDocument(uri);
    await vscode.window.showTextDocument(doc);
    const mapc = vscode.extensions.getExtension('open-rmf.mapc');
    out.push(`extension ${mapc ? 'found' : 'missing'} ${mapc && mapc.isActive ? 'active' : 'inactive'}`);
    const has = (code) => lines('', uri).some((l) => l.split(' ')[2] === code);
    if (await waitFor(uri, () => has('E0201'))) {
      out.push(...lines('open', uri));
      // Go to the definition of the `4' of `[1, 4,' (what F12 asks): the second `pantry'.
      const text = doc.getText().split('\n');
      const at = text.findIndex((l) => l.includes('[1, 4,'));
      const pos = new vscode.Position(at, text[at].indexOf('[1, 4,') + 4);
      const defs = await vscode.commands.executeCommand('vscode.executeDefinitionProvider', uri, pos);
      for (const d of defs || []) {
        const r = d.targetSelectionRange || d.targetRange || d.range;
        out.push(`definition ${r.start.line + 1}:${r.start.character + 1}`);
      }
      const line = doc.getText().split('\n').findIndex((l) => l.includes('[3, 3,'));
      const edit = new vscode.WorkspaceEdit();
      edit.delete(uri, new vscode.Range(line, 0, line + 1, 0));
      await vscode.workspace.applyEdit(edit);
      if (await waitFor(uri, () => !has('E0201'))) {
        out.push(...lines('edited', uri));
      } else {
        out.push("timeout waiting for the edit's diagnostics");
      }
    } else {
      out.push('timeout waiting for diagnostics');
    }
  } catch (e) {
    out.push(`error ${e && e.stack ? e.stack : e}`);
  }
  fs.writeFileSync(path.join(dir, 'diagnostics.txt'), out.join('\n') + '\n');
  fs.writeFileSync(path.join(dir, 'done.txt'), '');
}

module.exports = { activate };
