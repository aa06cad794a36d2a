#!/usr/bin/env bash
# Opens the HTML report in a real headless browser (Debian's Chromium), as a reader would from
# the file system: fails if the page logs anything to the console (errors, uncaught exceptions,
# failed loads) or if its script did not run, and saves a screenshot.
#
# Usage: verification/report/browser-test.sh [PAGE.html] [SCREENSHOT.png]
# A self-test first proves that the check can fail: a page with a console error must be refused.
set -euo pipefail
page=${1:-reports/index.html}
shot=${2:-reports/index.png}
chrome=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
if [ -z "$chrome" ]; then
  echo "browser-test: no Chromium found (apt-get install chromium)" >&2
  exit 2
fi
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
       --disable-background-networking --disable-component-update --disable-sync
       --disable-dev-shm-usage --allow-file-access-from-files)

# run_page URL LOG [extra flags...]: loads the page, console messages go to LOG
run_page() {
  local url=$1 log=$2; shift 2
  local profile; profile=$(mktemp -d)
  timeout 120 "$chrome" "${flags[@]}" --user-data-dir="$profile" --enable-logging=stderr --v=0 \
    "$@" "$url" 2>"$log" || true
  rm -rf "$profile"
}

console_problems() { grep -E "CONSOLE|Uncaught|ERR_FILE_NOT_FOUND|Failed to load" "$1" || true; }

# self-test: a page with a console error must be caught
tmp=$(mktemp -d)
cat > "$tmp/bad.html" <<'HTML'
<!DOCTYPE html><html><body><script>console.error("deliberate error"); undefinedFunction();</script></body></html>
HTML
run_page "file://$tmp/bad.html" "$tmp/bad.log" --dump-dom >/dev/null
if [ -z "$(console_problems "$tmp/bad.log")" ]; then
  echo "browser-test: self-test failed: a console error went unnoticed (log format changed?)" >&2
  cat "$tmp/bad.log" >&2
  exit 1
fi

[ -f "$page" ] || { echo "browser-test: $page not found (run geodesic verify first)" >&2; exit 2; }
url="file://$(realpath "$page")"
run_page "$url" "$tmp/dom.log" --dump-dom > "$tmp/dom.html"
problems=$(console_problems "$tmp/dom.log")
if [ -n "$problems" ]; then
  echo "browser-test: $page logged to the console:" >&2
  echo "$problems" >&2
  exit 1
fi
grep -q 'data-js="ready"' "$tmp/dom.html" || { echo "browser-test: the page's script did not run" >&2; exit 1; }
grep -q 'id="matrix"' "$tmp/dom.html" || { echo "browser-test: no compliance matrix in the page" >&2; exit 1; }
svgs=$( (grep -o '<svg' "$tmp/dom.html" || true) | wc -l)
run_page "$url" "$tmp/shot.log" --window-size=1400,3000 --screenshot="$(realpath -m "$shot")" >/dev/null
[ -s "$shot" ] || { echo "browser-test: no screenshot written" >&2; exit 1; }
echo "browser-test: $page loaded in $("$chrome" --version 2>/dev/null | head -1): no console message, script ran, $svgs inline plots; screenshot $shot"
rm -rf "$tmp"
