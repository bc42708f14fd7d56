#!/usr/bin/env bash
# The viewer's end-to-end test in a real browser (ctest: Viewer.Browser):
#   tests/browser/run.sh MANYLIGHT_BINARY OUTPUT_DIR
# Needs node, Debian's chromium and puppeteer-core (`scripts/setup --dev` installs them: the
# packages, then `npm ci` here). Where one is missing it skips (exit 77) and says which, unless
# MANYLIGHT_REQUIRE_SHARED=1 (CI), where it fails.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
chromium=${CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
missing=()
command -v node >/dev/null 2>&1 || missing+=("node (Debian: nodejs)")
[ -n "$chromium" ] && [ -x "$chromium" ] || missing+=("chromium (Debian: chromium)")
[ -d "$here/node_modules/puppeteer-core" ] || missing+=("puppeteer-core (npm ci --prefix tests/browser)")
if [ ${#missing[@]} -gt 0 ]; then
  echo "Viewer.Browser: skipped: missing ${missing[*]}; scripts/setup --dev installs them"
  [ "${MANYLIGHT_REQUIRE_SHARED:-0}" = 1 ] && { echo "MANYLIGHT_REQUIRE_SHARED=1: failing"; exit 1; }
  exit 77
fi
export CHROMIUM="$chromium"
exec node "$here/viewer_test.mjs" "$@"
