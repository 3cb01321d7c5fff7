#!/usr/bin/env bash
# Render reports/munro/index.html and reports/kubo/index.html in headless Chromium and check that
# every image loaded (naturalWidth > 0). Needs Debian's chromium (apt-get install chromium); not
# part of the default test suite, which checks the referenced PNG/SVG files exist instead.
set -eu
cd "$(dirname "$0")/.."
command -v chromium >/dev/null || { echo "chromium not installed: apt-get install -y chromium"; exit 2; }
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --user-data-dir="$(mktemp -d)")
status=0
for r in munro kubo; do
  page="reports/$r/index.html"
  [ -f "$page" ] || { echo "$page missing: run cargo run --release -- validate $r"; exit 2; }
  # Append a script that marks every image as loaded or broken, then dump the DOM after load.
  probe=$(mktemp --suffix=.html)
  sed 's#</body>#<script>window.addEventListener("load",()=>{for(const i of document.images){i.setAttribute("data-ok", i.complete \&\& i.naturalWidth>0 ? "yes":"no")}})</script></body>#' "$page" > "reports/$r/.probe.html"
  dom=$(chromium "${flags[@]}" --virtual-time-budget=5000 --dump-dom "file://$PWD/reports/$r/.probe.html" 2>/dev/null)
  rm -f "reports/$r/.probe.html" "$probe"
  ok=$(grep -o 'data-ok="yes"' <<<"$dom" | wc -l || true)
  bad=$(grep -o 'data-ok="no"' <<<"$dom" | wc -l || true)
  echo "$page: $ok images rendered, $bad broken"
  if [ "$bad" -ne 0 ] || [ "$ok" -eq 0 ]; then status=1; fi
done
exit $status
