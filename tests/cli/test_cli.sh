#!/usr/bin/env bash
# End-to-end tests of the clustersurf CLI on the default input (the npm bunny).
# Usage: test_cli.sh CLI DEFAULT_DATA_DIR SHARED_DATA_DIR. Exit 77 (skip) without the bunny.
set -uo pipefail
cli=$1
data=$2
bunny="$data/bunny.ply"
if [ ! -f "$bunny" ]; then
  echo "skip: $bunny is absent (run scripts/setup)"
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
check() {  # check "what" command...
  local what=$1
  shift
  if "$@"; then echo "ok   $what"; else echo "FAIL $what"; failures=$((failures + 1)); fi
}
json_get() { /usr/bin/env node -e "const j=JSON.parse(require('fs').readFileSync(0,'utf8'));console.log(j$1)"; }

check "--version" bash -c "'$cli' --version | grep -q clustersurf"
for sub in convert stats reconstruct info mesh; do
  check "$sub --help" bash -c "'$cli' $sub --help | grep -qi usage"
done
points=$("$cli" --json stats "$bunny" | json_get .points)
check "stats --json reports 1839 points" [ "$points" = 1839 ]

for ext in xyz obj ply; do
  "$cli" -q convert "$bunny" "$tmp/b.$ext"
  n=$("$cli" --json stats "$tmp/b.$ext" | json_get .points)
  check "convert to .$ext keeps 1839 points" [ "$n" = 1839 ]
done
"$cli" -q convert "$bunny" "$tmp/sub.ply" --subsample 100
check "convert --subsample 100" [ "$("$cli" --json stats "$tmp/sub.ply" | json_get .points)" = 100 ]

# Reconstruct + info + mesh.
"$cli" -q reconstruct "$bunny" -o "$tmp/b.cstree" --mesh "$tmp/m.ply"
check "reconstruct wrote a tree" [ -s "$tmp/b.cstree" ]
check "reconstruct wrote a mesh" [ -s "$tmp/m.ply" ]
leaves=$("$cli" --json info "$tmp/b.cstree" | json_get .leaves)
check "info --json has leaves > 10" [ "$leaves" -gt 10 ]
"$cli" -q reconstruct "$bunny" -o "$tmp/c.cstree"
check "same input gives the same tree bytes" cmp -s "$tmp/b.cstree" "$tmp/c.cstree"
"$cli" -q --threads 1 reconstruct "$bunny" -o "$tmp/d.cstree"
check "one thread gives the same tree bytes" cmp -s "$tmp/b.cstree" "$tmp/d.cstree"
tris=$("$cli" --json mesh "$tmp/b.cstree" -o "$tmp/m2.obj" --resolution 64 | json_get .triangles)
check "mesh --json reports triangles" [ "$tris" -gt 1000 ]

# Bad input: clear message naming the file, exit code 3, no output left behind.
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 oops 0\n2 2 2\n' > "$tmp/bad.ply"
"$cli" stats "$tmp/bad.ply" 2> "$tmp/err.txt"
code=$?
check "malformed file exits with 3" [ "$code" = 3 ]
check "message names file and line" grep -q "bad.ply:9" "$tmp/err.txt"
"$cli" -q convert "$tmp/bad.ply" "$tmp/never.ply"
check "failed convert leaves no output" [ ! -e "$tmp/never.ply" ]
echo keep > "$tmp/keep.ply"
"$cli" -q convert "$tmp/bad.ply" "$tmp/keep.ply"
check "failed convert leaves an existing output untouched" [ "$(cat "$tmp/keep.ply")" = keep ]
head -c 100 "$tmp/b.cstree" > "$tmp/trunc.cstree"
"$cli" info "$tmp/trunc.cstree" 2> "$tmp/err2.txt"
check "truncated tree exits with 3" [ $? = 3 ]
"$cli" stats "$tmp/missing.ply" 2> /dev/null
check "missing file exits with 4" [ $? = 4 ]
"$cli" reconstruct "$bunny" -o "$tmp/x.cstree" --alpha -1 2> /dev/null
check "invalid option exits with non-zero" [ $? != 0 ]
ls "$tmp"/.*.tmp* > /dev/null 2>&1
check "no temporary files left" [ $? != 0 ]

echo "$failures failure(s)"
[ "$failures" = 0 ]
