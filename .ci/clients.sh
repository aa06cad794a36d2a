#!/usr/bin/env bash
# The files geodesic writes, read by the programs their users already have, each run as its
# users run it (issue 52): the JUnit file validated against the Jenkins xUnit plugin's
# junit-10.xsd with xmlschema and parsed with junitparser and xunitparser; vcd.csv and vcd.xlsx
# read with pandas and openpyxl, their value, limit and margin columns numbers. Pinned
# versions from PyPI in a venv under target/ (reused while the pins are unchanged).
# junit-10.xsd is the copy pytest's source distribution ships (testing/example_scripts/), the
# same bytes as the plugin's (src/main/resources/.../model/xsd/junit-10.xsd, MIT licence):
# checked by its SHA-256.
# Usage: .ci/clients.sh REPORTS_DIR JUNIT_FILE
set -euo pipefail
reports=${1:?usage: clients.sh REPORTS_DIR JUNIT_FILE}
junit=${2:?usage: clients.sh REPORTS_DIR JUNIT_FILE}
here=$(cd "$(dirname "$0")" && pwd)
venv="$here/../target/clients-venv"
pins="xmlschema==4.3.2 elementpath==5.1.4 junitparser==5.0.3 xunitparser==1.3.4 pandas==3.1.1 numpy==2.4.6 python-dateutil==4.0.0 tzdata==2026.6 openpyxl==3.1.5 et_xmlfile==2.0.0"
xsd_from="pytest==8.3.4"
xsd_sha256=a1a816f58d1bf95ebabf371994df0b9246dee66ea9572fbec4f9296f1b2c0ff6
if ! { [ -x "$venv/bin/python" ] && [ "$(cat "$venv/.pins" 2>/dev/null)" = "$pins $xsd_from" ]; }; then
  command -v python3 >/dev/null || { echo "python3 is needed for the client checks"; exit 1; }
  rm -rf "$venv"
  python3 -m venv "$venv"
  # shellcheck disable=SC2086
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check $pins
  tmp=$(mktemp -d)
  "$venv/bin/python" -m pip download --quiet --disable-pip-version-check --no-deps \
      --no-binary :all: "$xsd_from" -d "$tmp"
  tar -xzf "$tmp"/pytest-*.tar.gz -C "$tmp" --wildcards '*/testing/example_scripts/junit-10.xsd'
  cp "$tmp"/pytest-*/testing/example_scripts/junit-10.xsd "$venv/junit-10.xsd"
  rm -rf "$tmp"
  echo "$pins $xsd_from" > "$venv/.pins"
fi
echo "$xsd_sha256  $venv/junit-10.xsd" | sha256sum --check --quiet
"$venv/bin/python" "$here/clients.py" junit "$junit" "$venv/junit-10.xsd"
"$venv/bin/python" "$here/clients.py" vcd "$reports/vcd.csv" "$reports/vcd.xlsx"
