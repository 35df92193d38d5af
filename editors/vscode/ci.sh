#!/usr/bin/env bash
# The VS Code extension in CI (.ci/run): its npm packages as locked, a syntax check of
# extension.js, the TextMate grammar tests (test/*.il, test/*.stim) and the .vsix, built with
# @vscode/vsce. Needs node and the npm registry. Any failure ends CI (set -e).
set -euo pipefail
cd "$(dirname "$0")"
start=$SECONDS
# a cache kept between CI runs on one machine (a fresh HOME each run would download it all again)
export npm_config_cache="${npm_config_cache:-/var/tmp/mlc-npm-cache}"
npm ci --no-audit --no-fund --loglevel=error
node --check extension.js
npx --no-install vscode-tmgrammar-test -g syntaxes/il.tmLanguage.json -g syntaxes/stim.tmLanguage.json \
  "test/*.il" "test/*.stim"
npx --no-install vsce package --allow-missing-repository --skip-license -o "${VSIX:-mlc.vsix}" >/dev/null
echo "editors/vscode: grammar tests passed, ${VSIX:-mlc.vsix} built ($((SECONDS - start)) s)"
