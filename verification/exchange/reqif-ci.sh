#!/usr/bin/env bash
# The ReqIF check of CI with the release binary: export the built-in requirements (and, given a
# compliance.json, their verification status), validate both against the OMG ReqIF 1.2 schema
# with verification/exchange/validate-reqif.py, check the reference parser's counts of the other
# tools' test files (reqif-reference-counts.py --check), import the export, export the imported
# set again and require the same file apart from its CREATION-TIME.
# Usage: reqif-ci.sh GEODESIC_BINARY [compliance.json]   (GEODESIC_REQIF_VALIDATOR: a python)
set -euo pipefail
bin=$(realpath "$1")
matrix=${2:-}
[ -n "$matrix" ] && matrix=$(realpath "$matrix")
py=${GEODESIC_REQIF_VALIDATOR:?set GEODESIC_REQIF_VALIDATOR to a python with reqif and xmlschema}
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"   # no ./requirements here: the built-in set
"$bin" export reqif --out first.reqif
files=(first.reqif)
if [ -n "$matrix" ]; then
  "$bin" export reqif --matrix "$matrix" --out status.reqif
  files+=(status.reqif)
fi
"$py" "$here/validate-reqif.py" "${files[@]}"
# the reference parser's counts of the other tools' test files are the committed ones
"$py" "$here/reqif-reference-counts.py" --check "$here/tests/fixtures/tools"
"$bin" import reqif first.reqif --out imported
"$bin" export reqif --requirements imported --out second.reqif
if ! diff <(grep -v '<CREATION-TIME>' first.reqif) <(grep -v '<CREATION-TIME>' second.reqif) >/dev/null; then
  echo "ReqIF round trip changed the export:"
  diff <(grep -v '<CREATION-TIME>' first.reqif) <(grep -v '<CREATION-TIME>' second.reqif) | head -20
  exit 1
fi
echo "ReqIF round trip: export, import, export identical apart from CREATION-TIME"
