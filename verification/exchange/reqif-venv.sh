#!/usr/bin/env bash
# Creates (or reuses) a Python virtual environment at $1 with the pinned packages that validate
# ReqIF files: reqif (bundles the OMG ReqIF 1.2 schema and a validator), xmlschema, lxml and
# their dependencies. Idempotent: reinstalls only when the pins change.
set -euo pipefail
venv=${1:?usage: reqif-venv.sh VENV_DIR}
pins="reqif==0.1.0 xmlschema==4.3.2 elementpath==5.1.4 lxml==6.1.3 Jinja2==3.1.6 MarkupSafe==3.0.4 openpyxl==3.1.5 et_xmlfile==2.0.0"
if [ -x "$venv/bin/python" ] && [ "$(cat "$venv/.pins" 2>/dev/null)" = "$pins" ]; then
  echo "reusing $venv ($pins)"
  exit 0
fi
command -v python3 >/dev/null || { echo "python3 is needed for the ReqIF schema validator"; exit 1; }
rm -rf "$venv"
python3 -m venv "$venv"
# shellcheck disable=SC2086
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check $pins
echo "$pins" > "$venv/.pins"
"$venv/bin/python" -c 'import reqif, xmlschema, lxml; print("reqif validator ready:", reqif.__file__)'
