#!/usr/bin/env bash
# Render every HTML report under the given folders (default: reports) in headless Chromium and
# fail on a page that does not load, an image that does not render (naturalWidth 0), a link to a
# local file that is not there, or a console error. Installs Debian's chromium with apt-get when
# it is missing (`--install-only` does only that: .ci/run starts it while the tests build).
# With SCREENSHOTS=DIR, also saves a screenshot of each page's top to DIR.
# Called by .ci/run after the reports are regenerated; not part of `cargo test`.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v chromium >/dev/null; then
  echo "chromium not installed: installing Debian's chromium"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq chromium >/dev/null
fi
[ "${1:-}" != "--install-only" ] || exit 0

roots=("$@")
[ ${#roots[@]} -gt 0 ] || roots=(reports)
mapfile -t pages < <(find "${roots[@]}" -name '*.html' ! -name '.probe-*' | sort)
[ ${#pages[@]} -gt 0 ] || { echo "no HTML reports under ${roots[*]}"; exit 2; }

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
       --disable-background-networking --disable-component-update --disable-sync
       --user-data-dir="$profile")

# The probe runs after load: it appends to the body the count of images that rendered, the
# sources of those that did not, and every console error or uncaught exception recorded since
# the page started. (It holds no '&', '#' or backslash, which sed would read in its replacement.)
# Local link targets are checked by the shell below.
probe='<script>
(function(){
  var errors=[];
  var origError=console.error;
  console.error=function(){errors.push(Array.prototype.join.call(arguments," "));origError.apply(console,arguments);};
  window.addEventListener("error",function(e){errors.push("uncaught: "+(e.message||(e.target?e.target.src:"")||"error"));},true);
  window.addEventListener("load",function(){
    var ok=0,bad=[];
    for(const i of document.images){ if(i.complete){ if(i.naturalWidth>0){ok++;} else {bad.push(i.getAttribute("src"));} } else {bad.push(i.getAttribute("src"));} }
    var out=document.createElement("pre");out.id="probe-result";
    out.textContent="PROBE images-ok="+ok+" PROBE-BROKEN="+JSON.stringify(bad)+" PROBE-ERRORS="+JSON.stringify(errors)+" PROBE-END";
    document.body.appendChild(out);
  });
})();
</script>'

status=0
for page in "${pages[@]}"; do
  dir=$(dirname "$page")
  tmp="$dir/.probe-$(basename "$page")"
  # The probe goes first in <head> so that it sees errors raised while the page loads.
  sed "s#<head>#<head>${probe//$'\n'/ }#" "$page" > "$tmp"
  # Lazy images must load for the check: make them eager in the probe copy only.
  sed -i 's/ loading="lazy"//g' "$tmp"
  dom=$(timeout 120 chromium "${flags[@]}" --virtual-time-budget=10000 --dump-dom \
        "file://$(realpath "$tmp")" 2>/dev/null || true)
  rm -f "$tmp"
  # Only the probe's result element, not the probe's own source, which the DOM also holds.
  result=$(sed -n '/<pre id="probe-result">/,/<\/pre>/p' <<<"$dom")
  if ! grep -q "PROBE images-ok=[0-9]" <<<"$result"; then
    echo "FAIL $page: did not load"
    status=1
    continue
  fi
  result=$(tr '\n' ' ' <<<"$result")
  ok=$(sed 's/.*PROBE images-ok=\([0-9]*\).*/\1/' <<<"$result")
  broken=$(sed 's/.*PROBE-BROKEN=\(.*\) PROBE-ERRORS=.*/\1/' <<<"$result")
  errors=$(sed 's/.*PROBE-ERRORS=\(.*\) PROBE-END.*/\1/' <<<"$result")
  # Local link targets (href not starting with a scheme or #) must exist.
  missing=()
  while IFS= read -r href; do
    [ -n "$href" ] || continue
    case "$href" in http:*|https:*|mailto:*|\#*) continue ;; esac
    [ -e "$dir/${href%%#*}" ] || missing+=("$href")
  done < <(grep -o 'href="[^"]*"' "$page" | sed 's/^href="//; s/"$//' | sort -u)
  line="$page: $ok images rendered"
  if [ "$broken" != "[]" ] || [ "$errors" != "[]" ] || [ ${#missing[@]} -gt 0 ]; then
    echo "FAIL $line; broken images $broken; console errors $errors; missing link targets: ${missing[*]:-none}"
    status=1
  else
    echo "ok   $line, no console error, every local link target present"
  fi
  if [ -n "${SCREENSHOTS:-}" ]; then
    mkdir -p "$SCREENSHOTS"
    shot="$SCREENSHOTS/$(echo "${page%.html}" | tr '/' '_').png"
    timeout 120 chromium "${flags[@]}" --hide-scrollbars --window-size=1280,2000 \
      --virtual-time-budget=5000 --screenshot="$shot" "file://$(realpath "$page")" >/dev/null 2>&1 || true
  fi
done
exit $status
