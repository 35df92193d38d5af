// mlc for VS Code: starts `mlc lsp` and adds the commands build / run scenario / show ladder.
// Everything about the language is the server's (mlctool/lsp/); this file only finds `mlc`
// and wires commands, tasks and the debugger type to it.
"use strict";

const cp = require("child_process");
const fs = require("fs");
const os = require("os");
const path = require("path");
const vscode = require("vscode");
const { LanguageClient, TransportKind } = require("vscode-languageclient/node");

let client;
let output;

/** The mlc executable: the `mlc.path` setting, else the workspace's .venv, else `mlc` on PATH. */
function mlcPath(folder) {
  const configured = vscode.workspace.getConfiguration("mlc", folder && folder.uri).get("path");
  if (configured) {
    return folder ? configured.replace("${workspaceFolder}", folder.uri.fsPath) : configured;
  }
  const roots = folder ? [folder] : vscode.workspace.workspaceFolders || [];
  for (const root of roots) {
    for (const rel of [[".venv", "bin", "mlc"], [".venv", "Scripts", "mlc.exe"]]) {
      const candidate = path.join(root.uri.fsPath, ...rel);
      if (fs.existsSync(candidate)) {
        return candidate;
      }
    }
  }
  return "mlc";
}

function currentFolder() {
  const editor = vscode.window.activeTextEditor;
  if (editor) {
    const folder = vscode.workspace.getWorkspaceFolder(editor.document.uri);
    if (folder) {
      return folder;
    }
  }
  return (vscode.workspace.workspaceFolders || [])[0];
}

/** The folder of the nearest mlc.toml at or above `file` (the project the file belongs to). */
function projectDir(file) {
  let dir = path.dirname(file);
  for (;;) {
    if (fs.existsSync(path.join(dir, "mlc.toml"))) {
      return dir;
    }
    const up = path.dirname(dir);
    if (up === dir) {
      return path.dirname(file);
    }
    dir = up;
  }
}

/**
 * The files `mlc ladder` draws for FILE: the project's `sources` (mlc.toml in `cwd`) when FILE
 * is one of them (a module CALLs labels of the others: alone it does not check), else FILE.
 * Reads the `sources = ["...", ...]` array with a pattern, not a TOML parser (no npm package).
 */
function ladderFiles(file, cwd) {
  const toml = path.join(cwd, "mlc.toml");
  if (!fs.existsSync(toml)) {
    return [file];
  }
  const found = /^\s*sources\s*=\s*\[([^\]]*)\]/m.exec(fs.readFileSync(toml, "utf8"));
  const sources = found ? [...found[1].matchAll(/"([^"]+)"/g)].map((m) => path.resolve(cwd, m[1])) : [];
  return sources.includes(path.resolve(file)) ? sources : [file];
}

/** Run `mlc ARGS` as a task in the terminal, with the mlc problem matcher. */
function runTask(name, args, cwd) {
  const folder = currentFolder();
  const exec = new vscode.ProcessExecution(mlcPath(folder), args, { cwd });
  const task = new vscode.Task({ type: "mlc", command: args[0], args: args.slice(1) },
    folder || vscode.TaskScope.Workspace, name, "mlc", exec, ["$mlc"]);
  return vscode.tasks.executeTask(task);
}

function startClient(context) {
  if (!vscode.workspace.getConfiguration("mlc").get("lsp.enabled")) {
    return;
  }
  const command = mlcPath(currentFolder());
  const serverOptions = { command, args: ["lsp"], transport: TransportKind.stdio };
  const clientOptions = {
    // IL sources, and stimulus files (diagnostics as `mlc sim --stimulus`, completion, hover)
    documentSelector: [{ scheme: "file", language: "il" }, { scheme: "file", language: "stim" }],
    // mlc.toml and modules changed on disk: the server reads the projects again
    synchronize: { fileEvents: vscode.workspace.createFileSystemWatcher("**/{mlc.toml,*.il}") },
    outputChannel: output,
  };
  client = new LanguageClient("mlc", "mlc", serverOptions, clientOptions);
  client.start().catch((err) => {
    vscode.window.showErrorMessage(
      `mlc: could not start \`${command} lsp\` (${err.message || err}). Set "mlc.path" or create the project's .venv.`);
  });
  context.subscriptions.push({ dispose: () => client && client.stop() });
}

function showLadder(context) {
  const editor = vscode.window.activeTextEditor;
  if (!editor || editor.document.languageId !== "il") {
    vscode.window.showWarningMessage("mlc: open an IL file to show its ladder");
    return;
  }
  const file = editor.document.uri.fsPath;
  const cwd = projectDir(file);
  const out = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "mlc-ladder-")), "ladder.html");
  const panel = vscode.window.createWebviewPanel("mlcLadder", `Ladder: ${path.basename(file)}`,
    vscode.ViewColumn.Beside, { enableScripts: true });
  const draw = () => {
    const files = ladderFiles(file, cwd);
    cp.execFile(mlcPath(currentFolder()), ["ladder", ...files, "-o", out, "--title", path.basename(file)], { cwd },
      (err, _stdout, stderr) => {
        if (err) {
          panel.webview.html = `<pre>${escapeHtml(stderr || String(err))}</pre>`;
          return;
        }
        panel.webview.html = fs.readFileSync(out, "utf8");
      });
  };
  draw();
  const saved = vscode.workspace.onDidSaveTextDocument((doc) => {
    if (doc.uri.fsPath === file) {
      draw();
    }
  });
  panel.onDidDispose(() => saved.dispose(), null, context.subscriptions);
}

function escapeHtml(text) {
  return text.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

async function runScenario() {
  const editor = vscode.window.activeTextEditor;
  let stim = editor && editor.document.languageId === "stim" ? editor.document.uri.fsPath : undefined;
  if (!stim) {
    const found = await vscode.workspace.findFiles("**/*.stim", "**/node_modules/**");
    const pick = await vscode.window.showQuickPick(found.map((u) => vscode.workspace.asRelativePath(u)),
      { placeHolder: "scenario to run" });
    if (!pick) {
      return;
    }
    stim = found.find((u) => vscode.workspace.asRelativePath(u) === pick).fsPath;
  }
  const cwd = projectDir(stim);
  const name = path.basename(stim, ".stim");
  return runTask(`test ${name}`, ["test", "-k", name], cwd);
}

function activate(context) {
  output = vscode.window.createOutputChannel("mlc");
  context.subscriptions.push(output);
  context.subscriptions.push(
    vscode.commands.registerCommand("mlc.build", () => {
      const folder = currentFolder();
      const file = vscode.window.activeTextEditor && vscode.window.activeTextEditor.document.uri.fsPath;
      return runTask("build", ["build"], file ? projectDir(file) : folder && folder.uri.fsPath);
    }),
    vscode.commands.registerCommand("mlc.check", () => {
      const folder = currentFolder();
      const file = vscode.window.activeTextEditor && vscode.window.activeTextEditor.document.uri.fsPath;
      return runTask("check", ["check"], file ? projectDir(file) : folder && folder.uri.fsPath);
    }),
    vscode.commands.registerCommand("mlc.runScenario", runScenario),
    vscode.commands.registerCommand("mlc.showLadder", () => showLadder(context)),
    vscode.tasks.registerTaskProvider("mlc", {
      provideTasks: () => [],
      resolveTask: (task) => {
        const def = task.definition;
        const args = [def.command, ...(def.args || [])];
        return new vscode.Task(def, task.scope || vscode.TaskScope.Workspace, task.name, "mlc",
          new vscode.ProcessExecution(mlcPath(currentFolder()), args), ["$mlc"]);
      },
    }),
    // the debugger type `mlc`: the simulator's debug adapter (`mlc debug --dap`) over stdio
    vscode.debug.registerDebugAdapterDescriptorFactory("mlc", {
      createDebugAdapterDescriptor: (session) => {
        const folder = session.workspaceFolder || currentFolder();
        return new vscode.DebugAdapterExecutable(mlcPath(folder), ["debug", "--dap"],
          folder ? { cwd: folder.uri.fsPath } : undefined);
      },
    }),
  );
  startClient(context);
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate, mlcPath, projectDir };
