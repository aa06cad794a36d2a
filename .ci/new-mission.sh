#!/usr/bin/env bash
# `geodesic new mission` followed as docs/guide-mission.md says, outside the repository: the
# generated project's Cargo.toml names no absolute path; as generated, its own two commands
# (`cargo run -- test`, `cargo run -- verify --require-tests`) exit 0 with the tests column
# filled; the guide's step 3 applied as written (.ci/guide_mission_apply.py reads its blocks: a
# requirement, an input file, a check with its model, a traced test) and its commands run: the
# new requirement compliant, its traced test recorded, `verify --require-tests` exit 0; then it
# verifies and writes every report format, it gates against its own baseline, and editing its
# requirement's limit or its input file moves its verdict. Nothing inside the repository is
# edited. The project's `cargo run` runs with `--release --offline` (the target folder below
# holds the framework's crates in the release profile; the registry cache has the rest). Usage: .ci/new-mission.sh
# [GEODESIC_BINARY] (default target/release/geodesic); the project goes to a fresh temporary
# folder, built in the repository's target folder so that the framework's crates, compiled
# with the same profile and features, are reused.
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$PWD"
geodesic="${1:-$repo/target/release/geodesic}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export CARGO_TARGET_DIR="$repo/target"
fail() { echo "new-mission: $*" >&2; exit 1; }

"$geodesic" new mission demo-arm --path "$work/demo-arm" 2> "$work/new.err"
cat "$work/new.err"
cd "$work/demo-arm"
[ -f mission.yaml ] && [ -f requirements/structure.yaml ] && [ -f design.yaml ] && [ -f tests/traced.rs ] \
  || fail "the scaffold is missing files"
git -C "$repo" status --porcelain --untracked-files=no | grep -q . && echo "(the repository's tree was already dirty)"

# no absolute path in its manifest: this checkout has no network remote, so a relative path,
# said on standard error with how to share it
grep -E '(path|git) = "' Cargo.toml
grep -qE 'path = "/' Cargo.toml && fail "Cargo.toml names an absolute path"
if ! git -C "$repo" remote get-url origin 2>/dev/null | grep -qE '^(https?|ssh|git)://|^git@'; then
  grep -q 'path = "\.\./' Cargo.toml || fail "Cargo.toml: no relative path dependency"
  grep -q -- "--geodesic-git" "$work/new.err" || fail "no note on standard error about --geodesic-git"
fi

run() { cargo run --release --offline --quiet -- "$@"; }
bin="$CARGO_TARGET_DIR/release/demo-arm"

# before any run, `requirements show` names the project's own command, not cargo xtask
run requirements show DEMO-ARM-DEFL > "$work/show.txt" || fail "requirements show: not 0"
grep -q 'no recorded test run (`cargo run -- test`' "$work/show.txt" || { cat "$work/show.txt"; fail "requirements show does not name cargo run -- test"; }

# as generated: its own test command, then verify --require-tests, exit 0, tests column filled
run test > "$work/test.log" 2>&1 || { tail -30 "$work/test.log"; fail "cargo run -- test as generated: not 0"; }
grep -E "^recorded|^test result" "$work/test.log"
[ -s target/geodesic/test-run.json ] || fail "cargo run -- test wrote no target/geodesic/test-run.json"
run verify --require-tests --reports r0 --json > r0.json || fail "verify --require-tests as generated: not 0"
python3 - r0.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
row = {r["id"]: r for r in d["requirements"]}["DEMO-ARM-DEFL"]
assert row["status"] == "compliant" and row["tests"] and all(t["result"] == "passed" for t in row["tests"]), row
assert d["test_run"]["fresh"], d["test_run"]
print("as generated: test + verify --require-tests exit 0; DEMO-ARM-DEFL tests:", [t["test"] for t in row["tests"]])
PY

# docs/guide-mission.md, step 3, as written: a requirement, an input file, a check, a traced test
python3 "$repo/.ci/guide_mission_apply.py" "$repo/docs/guide-mission.md" .
# the run recorded before is stale now, and verify names the project's own command
set +e
run verify --require-tests --reports r0b > /dev/null 2> "$work/stale.err"; rc=$?
set -e
[ "$rc" = 1 ] || fail "verify --require-tests after the guide's edits, before the tests: exit $rc (expected 1)"
grep -q "STALE.*cargo run -- test" "$work/stale.err" || { cat "$work/stale.err"; fail "the stale run does not name cargo run -- test"; }
grep -q "cargo xtask" "$work/stale.err" && fail "verify in a generated project names cargo xtask"
python3 "$repo/.ci/guide_mission_apply.py" "$repo/docs/guide-mission.md" . --commands > "$work/guide.sh"
cat "$work/guide.sh"
grep -q "cargo run -- test" "$work/guide.sh" && grep -q "verify --require-tests" "$work/guide.sh" \
  || fail "the guide's step 3 does not end with the two commands"
sed -i 's/^cargo run -- /cargo run --release --offline --quiet -- /; s/verify --require-tests --reports reports/verify --require-tests --reports reports --json/' "$work/guide.sh"
bash -e "$work/guide.sh" > guide.json 2> "$work/guide.err" || { tail -30 "$work/guide.err"; fail "the guide's commands: not 0"; }
python3 - guide.json <<'PY'
import json, sys
text = open(sys.argv[1]).read()
d = json.loads(text[text.index("\n{") + 1:] if not text.startswith("{") else text)
rows = {r["id"]: r for r in d["requirements"]}
m = rows["DEMO-ARM-MASS"]
assert m["status"] == "compliant", m
assert any(t["test"].endswith("the_arm_meets_the_mass_limit") and t["result"] == "passed" for t in m["tests"]), m["tests"]
assert rows["DEMO-ARM-DEFL"]["status"] == "compliant"
print("guide step 3: DEMO-ARM-MASS", m["status"], m.get("value_text", ""), "traced:", [t["test"] for t in m["tests"]])
PY
cargo build --release --offline --quiet

# verifies as generated (the default command is verify), every report format written
set +e
"$bin" --reports r1 --json > r1.json; rc=$?
set -e
[ "$rc" = 0 ] || fail "verify as generated: exit $rc (expected 0)"
for f in compliance.json compliance.md vcd.md vcd.csv vcd.xlsx vcd.html index.html; do
  [ -s "r1/$f" ] || fail "r1/$f not written"
done
python3 - r1.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
rows = {r["id"]: r for r in d["requirements"]}
assert rows["DEMO-ARM-DEFL"]["status"] == "compliant", rows
assert d["run"]["inputs"]["design"]["label"] == "design.yaml", d["run"]["inputs"]
print("verify as generated: DEMO-ARM-DEFL", rows["DEMO-ARM-DEFL"]["status"], rows["DEMO-ARM-DEFL"].get("value_text", ""))
PY

# JUnit and ReqIF
"$bin" verify --reports r1b --junit junit.xml > /dev/null
grep -q "<testcase" junit.xml || fail "no JUnit test case"
"$bin" export reqif --out r1/requirements.reqif --matrix r1/compliance.json
"$bin" export-reqif --out r1/requirements-alias.reqif --matrix r1/compliance.json
cmp <(grep -v "CREATION-TIME\|IDENTIFIER=\"_" r1/requirements.reqif) <(grep -v "CREATION-TIME\|IDENTIFIER=\"_" r1/requirements-alias.reqif) > /dev/null \
  || echo "(export-reqif and export reqif differ beyond time and identifiers)"
grep -q "DEMO-ARM-DEFL" r1/requirements.reqif || fail "ReqIF export lacks the requirement"

# the gate: the same tree against its own baseline passes
"$bin" verify --baseline r1/compliance.json --reports r2 > /dev/null || fail "gate on an unchanged tree: not 0"

# a tighter limit: non-compliant (exit 1), and the gate names the regression
sed -i 's/limit: "<= 2 mm"/limit: "<= 1 mm"/' requirements/structure.yaml
set +e
"$bin" verify --reports r3 > /dev/null; rc_verify=$?
"$bin" verify --baseline r1/compliance.json --reports r4 2> gate.err > /dev/null; rc_gate=$?
set -e
[ "$rc_verify" = 1 ] || fail "limit 1 mm: verify exit $rc_verify (expected 1)"
[ "$rc_gate" = 1 ] || fail "limit 1 mm: gate exit $rc_gate (expected 1)"
grep -q "DEMO-ARM-DEFL" gate.err || fail "the gate does not name DEMO-ARM-DEFL"
sed -i 's/limit: "<= 1 mm"/limit: "<= 2 mm"/' requirements/structure.yaml

# a thinner arm in the input file: the verdict moves too
sed -i 's/thickness_m: 0.002/thickness_m: 0.0015/' design.yaml
set +e
"$bin" verify --reports r5 > /dev/null; rc=$?
set -e
[ "$rc" = 1 ] || fail "thinner arm: verify exit $rc (expected 1)"
echo "new-mission: no absolute path; as generated cargo run -- test + verify --require-tests exit 0; the guide's requirement, input, check and traced test: compliant and recorded; every report, JUnit, ReqIF, gate 0 unchanged / 1 on a tighter limit, a thinner arm non-compliant"
