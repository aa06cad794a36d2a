#!/usr/bin/env bash
# The files geodesic writes, read by the programs their users already have, each run as its
# users run it (issue 52): the JUnit file validated against the Jenkins xUnit plugin's
# junit-10.xsd with xmlschema and parsed with junitparser and xunitparser; vcd.csv and vcd.xlsx
# read with pandas and openpyxl, their value, limit and margin columns numbers; every recorded
# --json document (the gate's compliance.json, fit, diagnose and discover on the public
# examples, effects) validated with `jsonschema` against `geodesic schema COMMAND`, and a field
# renamed in the recorded compliance.json shown to fail that check. Pinned
# versions from PyPI in a venv under target/ (reused while the pins are unchanged).
# junit-10.xsd is the copy pytest's source distribution ships (testing/example_scripts/), the
# same bytes as the plugin's (src/main/resources/.../model/xsd/junit-10.xsd, MIT licence):
# checked by its SHA-256.
# StrictDoc (pinned with its dependencies in .ci/strictdoc-requirements.txt, its own venv)
# converts both ReqIF exports (with and without the matrix) with its default options; its
# export back to ReqIF imports into geodesic with a warning for each derivation margin it
# dropped.
# Usage: .ci/clients.sh REPORTS_DIR JUNIT_FILE GEODESIC_BINARY
set -euo pipefail
usage="usage: clients.sh REPORTS_DIR JUNIT_FILE GEODESIC_BINARY"
reports=$(realpath "${1:?$usage}")
junit=$(realpath "${2:?$usage}")
bin=$(realpath "${3:?$usage}")
here=$(cd "$(dirname "$0")" && pwd)
venv="$here/../target/clients-venv"
pins="xmlschema==4.3.2 elementpath==5.1.4 junitparser==5.0.3 xunitparser==1.3.4 pandas==3.1.1 numpy==2.4.6 python-dateutil==4.0.0 tzdata==2026.6 openpyxl==3.1.5 et_xmlfile==2.0.0 jsonschema==4.26.0 jsonschema-specifications==2025.9.1 referencing==0.37.0 rpds-py==2026.9.1 attrs==26.1.0 typing-extensions==4.16.0"
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

# venv DIR REQUIREMENTS_FILE: DIR made (or reused while the pinned file is unchanged)
venv_from() {
  local dir=$1 reqs=$2 pins
  pins=$(sha256sum "$reqs" | cut -d' ' -f1)
  if ! { [ -x "$dir/bin/python" ] && [ "$(cat "$dir/.pins" 2>/dev/null)" = "$pins" ]; }; then
    rm -rf "$dir"
    python3 -m venv "$dir"
    "$dir/bin/python" -m pip install --quiet --disable-pip-version-check -r "$reqs"
    echo "$pins" > "$dir/.pins"
  fi
}

# StrictDoc, as its users run it
sd="$here/../target/strictdoc-venv"
venv_from "$sd" "$here/strictdoc-requirements.txt"
# Sphinx with sphinx-needs (pinned in .ci/sphinx-requirements.txt)
sx="$here/../target/sphinx-venv"
venv_from "$sx" "$here/sphinx-requirements.txt"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(
  cd "$work"   # no ./requirements here: the built-in set
  "$bin" export reqif --out g.reqif >/dev/null
  "$bin" export reqif --matrix "$reports/compliance.json" --out gm.reqif >/dev/null
  for f in g gm; do
    "$sd/bin/strictdoc" convert "$f.reqif" "sdoc-$f" >"$f.log" 2>&1 \
      || { tail -5 "$f.log"; echo "clients: strictdoc convert $f.reqif failed"; exit 1; }
  done
  n=$(grep -c '^UID: ' sdoc-gm/*.sdoc)
  "$sd/bin/strictdoc" export sdoc-g --formats reqif-sdoc --output-dir back >back.log 2>&1 \
      || { tail -5 back.log; echo "clients: strictdoc export reqif-sdoc failed"; exit 1; }
  "$bin" import reqif back/reqif/output.reqif --out imported --json >import.json 2>/dev/null
  "$venv/bin/python" - "$n" <<'PY'
import json, sys
n = int(sys.argv[1])
imp = json.load(open("import.json"))
warned = [w for w in imp["warnings"] if "no geodesic.DerivationMargin: recomputed" in w["cause"]]
count = imp["requirements"] if isinstance(imp.get("requirements"), int) else len(imp["requirements"])
if count != n or not warned:
    sys.exit(f"clients: StrictDoc round trip: {count} of {n} requirements back, {len(warned)} margin warnings")
print(f"strictdoc: converts both exports ({n} requirements with UIDs); its ReqIF export imports "
      f"back with {count} requirements and {len(warned)} warnings of a recomputed margin")
PY
)

# sphinx-needs, as a Sphinx project loads needs.json: needimport and a needtable, -W
(
  cd "$work"
  mkdir sphinx
  "$bin" export needs --matrix "$reports/compliance.json" --out sphinx/needs.json >/dev/null
  cat > sphinx/conf.py <<'PY'
project = "geodesic needs"
extensions = ["sphinx_needs"]
needs_types = [dict(directive="req", title="Requirement", prefix="", color="#BFD8D2", style="node")]
needs_fields = {f: {"default": ""} for f in ["verdict", "basis", "limit", "value", "unit", "margin",
                                             "derivation_margin", "source", "method", "family"]}
PY
  printf 'Matrix\n======\n\n.. needimport:: needs.json\n\n.. needtable::\n   :columns: id, title, status, verdict, margin\n' > sphinx/index.rst
  "$sx/bin/sphinx-build" -W -q -b html sphinx sphinx/_build >sphinx.log 2>&1 \
      || { tail -5 sphinx.log; echo "clients: sphinx-needs does not load needs.json"; exit 1; }
  n=$(grep -o 'needs_amount": [0-9]*' sphinx/needs.json | grep -o '[0-9]*$')
  echo "sphinx-needs: sphinx-build -W loads needs.json ($n needs) into a page with a needtable"
)

# the --json documents against their schemas (`geodesic schema COMMAND`, draft 2020-12)
(
  mkdir "$work/schemas" && cd "$work/schemas"
  examples="$here/../data/examples"
  cp "$reports/compliance.json" verify.json
  # OUT ARGS...: `geodesic ARGS` into OUT, its warnings into runs.log (shown if it fails)
  run() {
    local out=$1; shift
    "$bin" "$@" > "$out" 2>>runs.log || { tail -5 runs.log; echo "clients: geodesic $* failed"; exit 1; }
  }
  run fit.json fit "$examples/tmmf-adhesion.yaml" --effects needle_contact,tip_contact,tip_adhesion \
      --reports r --json -q
  for pair in tmmf-adhesion:needle_contact,tip_contact rt-plunger:piezo; do
    ex=${pair%%:*}; base=${pair#*:}
    run "diagnose.$ex.json" diagnose "$examples/$ex.yaml" --effects "$base" --reports r --json -q
    run "discover.$ex.json" discover "$examples/$ex.yaml" --effects "$base" --reports r --json -q
  done
  run effects.json effects --json
  rm -rf r
  for c in verify fit diagnose discover effects; do run "$c.schema.json" schema "$c"; done
  "$venv/bin/python" "$here/clients.py" schema .
  # the check can fail: the recorded compliance.json with `summary` renamed is refused (exit 1)
  mkdir mutated
  cp verify.schema.json mutated/
  sed 's/^  "summary": {/  "summary_renamed": {/' verify.json > mutated/verify.json
  cmp -s verify.json mutated/verify.json && { echo "clients: the mutation did not apply"; exit 1; }
  if "$venv/bin/python" "$here/clients.py" schema mutated > mutated.log; then
    echo "clients: a renamed field in compliance.json passed the schema check"; exit 1
  fi
  grep -q "verify: \$: 'summary' is a required property" mutated.log \
    || { cat mutated.log; echo "clients: the schema check did not name the renamed field"; exit 1; }
  echo "schema: compliance.json with summary renamed is refused: $(grep -m1 'verify: ' mutated.log)"
)
