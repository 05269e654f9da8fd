#!/usr/bin/env bash
# End-to-end tests of the `clustersurf` CLI: version and help, stats, convert between formats
# (and back), reductions, reconstruct/info/mesh, exit codes and messages for bad input, and
# atomic output.
#
# Usage: test_cli.sh CLI_BINARY DEFAULT_DATA_DIR [SHARED_DATA_DIR]
# Exits 77 (skipped) when DEFAULT_DATA_DIR/bunny.ply is missing (run scripts/setup).
set -uo pipefail

cli=${1:?usage: test_cli.sh CLI DEFAULT_DATA_DIR [SHARED_DATA_DIR]}
data=${2:?usage: test_cli.sh CLI DEFAULT_DATA_DIR [SHARED_DATA_DIR]}
shared=${3:-}
bunny_mesh="$data/bunny.ply"  # the default input: a mesh of 1,839 vertices
testdata="$(cd "$(dirname "$0")/../data" && pwd)"  # tests/data: small files kept with the tests

if [ ! -x "$cli" ]; then
  echo "CLI binary $cli not found or not executable" >&2
  exit 1
fi
if [ ! -f "$bunny_mesh" ]; then
  echo "SKIP: $bunny_mesh is missing (run scripts/setup)"
  exit 77
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/clustersurf-cli-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# Most checks want a small cloud: the mesh's 1,839 vertices (with normals from its faces).
bunny="$tmp/bunny-vertices.ply"
"$cli" -q convert --ascii --mesh-samples 0 "$bunny_mesh" "$bunny" || { echo "cannot write $bunny" >&2; exit 1; }

passed=0
failed=0
ok() { passed=$((passed + 1)); echo "ok   - $1"; }
not_ok() {
  failed=$((failed + 1))
  echo "FAIL - $1"
  [ -n "${2:-}" ] && printf '       %s\n' "$2"
  return 0
}
check() {  # check NAME COMMAND...: passes when the command succeeds
  local name=$1
  shift
  if "$@"; then ok "$name"; else not_ok "$name"; fi
}

# run ARGS...: runs the CLI, leaving stdout in $out, stderr in $err and the exit code in $rc.
run() {
  "$cli" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
  out=$(cat "$tmp/stdout")
  err=$(cat "$tmp/stderr")
}

# json_field FIELD: prints a top-level field of the JSON in $out.
json_field() {
  if command -v python3 >/dev/null 2>&1; then
    python3 -c 'import json, sys; v = json.loads(sys.stdin.read())[sys.argv[1]]; print(json.dumps(v) if isinstance(v, (bool, list, dict)) else v)' "$1" <<<"$out"
  else
    grep -o "\"$1\": *[^,}]*" <<<"$out" | head -n1 | sed 's/^[^:]*: *//; s/"//g'
  fi
}

# count FILE: the point count `stats --json` reports for FILE (empty on failure).
count() {
  run --json stats "$1"
  [ "$rc" -eq 0 ] && json_field points
}

expect_eq() {  # expect_eq NAME ACTUAL EXPECTED
  if [ "$2" = "$3" ]; then ok "$1"; else not_ok "$1" "got '$2', expected '$3'"; fi
}
expect_rc() {  # expect_rc NAME EXPECTED (after run)
  if [ "$rc" -eq "$2" ]; then ok "$1"; else not_ok "$1" "exit code $rc, expected $2; stderr: $err"; fi
}
expect_contains() {  # expect_contains NAME HAYSTACK NEEDLE
  if [[ "$2" == *"$3"* ]]; then ok "$1"; else not_ok "$1" "'$3' not found in: $2"; fi
}
no_new_files() {  # no_new_files NAME DIR EXPECTED_LISTING
  local now
  now=$(ls -A "$2")
  if [ "$now" = "$3" ]; then ok "$1"; else not_ok "$1" "files now: $(echo $now)"; fi
}

# --- version and help -------------------------------------------------------------------------
run --version
expect_rc "--version exits 0" 0
if [[ "$out" =~ ^clustersurf\ [0-9]+\.[0-9]+\.[0-9]+ ]]; then ok "--version prints 'clustersurf X.Y.Z'"; else not_ok "--version output" "$out"; fi

run --help
expect_rc "--help exits 0" 0
for sub in convert stats reconstruct info mesh render view; do
  expect_contains "--help lists $sub" "$out" "$sub"
done
for sub in convert stats reconstruct info mesh render view; do
  run "$sub" --help
  expect_rc "$sub --help exits 0" 0
  expect_contains "$sub --help shows usage" "$out" "Usage:"
done
run convert --help
expect_contains "convert --help documents --subsample" "$out" "--subsample"
expect_contains "convert --help documents --voxel" "$out" "--voxel"

run
if [ "$rc" -ne 0 ]; then ok "no subcommand is a usage error"; else not_ok "no subcommand is a usage error"; fi
run stats
if [ "$rc" -ne 0 ]; then ok "stats without input is a usage error"; else not_ok "stats without input is a usage error"; fi

# --- stats --------------------------------------------------------------------------------------
run --json stats "$bunny"
expect_rc "stats --json exits 0" 0
expect_eq "stats --json: bunny has 1839 points" "$(json_field points)" 1839
for field in bbox_min bbox_max diagonal mean_spacing median_spacing has_normals has_colors; do
  if json_field "$field" >/dev/null 2>&1 && [ -n "$(json_field "$field")" ]; then ok "stats --json has $field"; else not_ok "stats --json has $field" "$out"; fi
done
run stats "$bunny"
expect_rc "stats (human) exits 0" 0
expect_contains "stats (human) shows the count" "$out" "1839"
run -q --json stats "$bunny"
expect_eq "-q --json still prints the JSON" "$(json_field points)" 1839

# A small mesh is read as samples of its faces; --mesh-samples 0 reads its vertices.
run --json stats "$bunny_mesh"
expect_eq "a mesh of 1839 vertices is read as 100000 samples of its faces" "$(json_field points)" 100000
expect_contains "reading a mesh's samples says so" "$err" "1839 vertices, read as 100000 points"
run --json stats --mesh-samples 0 "$bunny_mesh"
expect_eq "--mesh-samples 0 reads the vertices" "$(json_field points)" 1839
run --json stats --mesh-samples 1000 "$bunny_mesh"
expect_eq "a mesh with more vertices than --mesh-samples is read as its vertices" "$(json_field points)" 1839

# --- convert and back ---------------------------------------------------------------------------
run convert --ascii "$bunny" "$tmp/a.ply"
expect_rc "convert to ascii PLY" 0
expect_eq "ascii PLY header" "$(sed -n 2p "$tmp/a.ply")" "format ascii 1.0"
expect_eq "ascii PLY has 1839 points" "$(count "$tmp/a.ply")" 1839

run convert "$bunny" "$tmp/b.ply"
expect_rc "convert to binary PLY" 0
expect_eq "binary PLY header" "$(sed -n 2p "$tmp/b.ply")" "format binary_little_endian 1.0"
expect_eq "binary PLY has 1839 points" "$(count "$tmp/b.ply")" 1839

run convert "$bunny" "$tmp/c.xyz"
expect_rc "convert to XYZ" 0
expect_eq "XYZ has 1839 lines" "$(wc -l <"$tmp/c.xyz" | tr -d ' ')" 1839
expect_eq "XYZ has 1839 points" "$(count "$tmp/c.xyz")" 1839

run convert "$bunny" "$tmp/d.obj"
expect_rc "convert to OBJ" 0
expect_eq "OBJ has 1839 v lines" "$(grep -c '^v ' "$tmp/d.obj")" 1839
expect_eq "OBJ has 1839 points" "$(count "$tmp/d.obj")" 1839

# ... and back to PLY from each, with the same count and the same bounding box.
run --json stats "$bunny"
bbox_ref="$(json_field bbox_min) $(json_field bbox_max)"
for src in a.ply c.xyz d.obj; do
  run convert --double "$tmp/$src" "$tmp/back-$src.ply"
  expect_rc "convert $src back to PLY" 0
  expect_eq "$src back to PLY keeps 1839 points" "$(count "$tmp/back-$src.ply")" 1839
  run --json stats "$tmp/back-$src.ply"
  expect_eq "$src back to PLY keeps the bbox" "$(json_field bbox_min) $(json_field bbox_max)" "$bbox_ref"
done

run --json convert "$bunny" "$tmp/j.ply"
expect_eq "convert --json reports points" "$(json_field points)" 1839
expect_eq "convert --json reports points_read" "$(json_field points_read)" 1839

# --- reductions ---------------------------------------------------------------------------------
run --json convert --subsample 100 "$bunny" "$tmp/s1.ply"
expect_rc "convert --subsample 100" 0
expect_eq "--subsample 100 reports 100 points" "$(json_field points)" 100
expect_eq "--subsample 100 writes 100 points" "$(count "$tmp/s1.ply")" 100
run convert --subsample 100 "$bunny" "$tmp/s2.ply"
check "--subsample is deterministic" cmp -s "$tmp/s1.ply" "$tmp/s2.ply"
run convert --subsample 100 --seed 2 "$bunny" "$tmp/s3.ply"
if cmp -s "$tmp/s1.ply" "$tmp/s3.ply"; then not_ok "--seed changes the subset"; else ok "--seed changes the subset"; fi
run convert --subsample 5000 "$bunny" "$tmp/s4.ply"
expect_eq "--subsample above the size keeps every point" "$(count "$tmp/s4.ply")" 1839

run --json convert --voxel 0.5 "$bunny" "$tmp/v.ply"
expect_rc "convert --voxel 0.5" 0
voxel_points=$(json_field points)
if [ -n "$voxel_points" ] && [ "$voxel_points" -gt 0 ] && [ "$voxel_points" -lt 1839 ]; then
  ok "--voxel 0.5 reduces the cloud ($voxel_points points)"
else
  not_ok "--voxel 0.5 reduces the cloud" "$out"
fi
expect_eq "--voxel output count matches the report" "$(count "$tmp/v.ply")" "$voxel_points"
run --json convert --voxel 100 "$bunny" "$tmp/v1.ply"
expect_eq "a voxel larger than the cloud leaves one point" "$(json_field points)" 1
run convert --voxel 0 "$bunny" "$tmp/v0.ply"
if [ "$rc" -ne 0 ] && [ ! -e "$tmp/v0.ply" ]; then ok "--voxel 0 is rejected, no output"; else not_ok "--voxel 0 is rejected" "rc $rc"; fi

# --- bad input: exit codes, messages, atomic output ---------------------------------------------
bad="$tmp/bad input.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n4 5 oops\n7 8 9\n' >"$bad"
mkdir "$tmp/out"
run stats "$bad"
expect_rc "malformed file: exit code 3" 3
expect_contains "malformed file: the message names the file and line" "$err" "$bad:9:"
expect_contains "malformed file: the message says what is wrong" "$err" "oops"

run convert "$bad" "$tmp/out/new.ply"
expect_rc "convert of a malformed file: exit code 3" 3
no_new_files "convert of a malformed file leaves no output (nor temporary) file" "$tmp/out" ""

printf 'keep me\n' >"$tmp/out/existing.ply"
before=$(cksum <"$tmp/out/existing.ply")
run convert "$bad" "$tmp/out/existing.ply"
expect_rc "failed convert onto an existing file: exit code 3" 3
expect_eq "an existing output file is untouched after a failed run" "$(cksum <"$tmp/out/existing.ply")" "$before"
no_new_files "no temporary file left beside it" "$tmp/out" "existing.ply"

for case in "empty.ply|" "trunc.ply|ply
format binary_little_endian 1.0
element vertex 100
property float x
property float y
property float z
end_header
0123456789" "cols.xyz|1 2 3
4 5 6 7 8
" "faces.obj|v 0 0 0
v 1 0 0
f 1 2 3
v x y z
"; do
  name=${case%%|*}
  printf '%s' "${case#*|}" >"$tmp/$name"
  run convert "$tmp/$name" "$tmp/out/x.ply"
  expect_rc "$name: exit code 3" 3
  expect_contains "$name: the message names the file" "$err" "$tmp/$name"
  no_new_files "$name: no output file" "$tmp/out" "existing.ply"
done

run convert "$tmp/does-not-exist.ply" "$tmp/out/x.ply"
expect_rc "missing input: exit code 4" 4
expect_contains "missing input: the message names the file" "$err" "does-not-exist.ply"
no_new_files "missing input: no output file" "$tmp/out" "existing.ply"

run convert "$tmp/out" "$tmp/out/x.ply"
expect_rc "a directory as input: exit code 4" 4
expect_contains "a directory as input: message" "$err" "is a directory"

run convert "$bunny" "$tmp/no-such-dir/x.ply"
expect_rc "unwritable output: exit code 4" 4
run convert "$bunny" "$tmp/out/x.vtk"
if [ "$rc" -ne 0 ] && [ ! -e "$tmp/out/x.vtk" ]; then ok "unknown output format is rejected, no output"; else not_ok "unknown output format" "rc $rc"; fi

# Non-finite coordinates: an error by default, dropped with a warning on request.
printf '1 2 3\n4 nan 6\n7 8 9\n' >"$tmp/nan.xyz"
run stats "$tmp/nan.xyz"
expect_rc "NaN coordinate: exit code 3" 3
expect_contains "NaN coordinate: message names the line" "$err" "$tmp/nan.xyz:2:"
run --json stats --drop-non-finite "$tmp/nan.xyz"
expect_rc "--drop-non-finite: exit code 0" 0
expect_eq "--drop-non-finite keeps 2 points" "$(json_field points)" 2
expect_contains "--drop-non-finite warns with the count" "$err" "dropped 1 of 3"

# The hostile-input table (tests/data/bad/expected.tsv): each file refused with exit code 3 and
# its message, no output written.
hostile="$(cd "$(dirname "$0")/../data/bad" && pwd)"
while IFS=$'\t' read -r name how message; do
  case "$name" in ''|'#'*) continue ;; esac
  case "$how" in
    cloud) run convert "$hostile/$name" "$tmp/out/x.ply" ;;
    mesh) run sample "$hostile/$name" -o "$tmp/out/x.ply" -n 10 ;;
    tree) run mesh "$hostile/$name" -o "$tmp/out/x.ply" ;;
  esac
  expect_rc "hostile $name: exit code 3" 3
  expect_contains "hostile $name: message" "$err" "$message"
  no_new_files "hostile $name: no output file" "$tmp/out" "existing.ply"
done <"$hostile/expected.tsv"

# --- reconstruct, info, mesh -------------------------------------------------------------------
run -q reconstruct "$bunny" -o "$tmp/b.cstree" --mesh "$tmp/m.ply"
expect_rc "reconstruct exits 0" 0
check "reconstruct wrote a tree" test -s "$tmp/b.cstree"
check "reconstruct wrote a mesh" test -s "$tmp/m.ply"
run --json info "$tmp/b.cstree"
expect_rc "info --json exits 0" 0
leaves=$(json_field leaves)
if [ -n "$leaves" ] && [ "$leaves" -gt 10 ]; then ok "info --json has leaves > 10 ($leaves)"; else not_ok "info --json leaves" "$out"; fi
run -q reconstruct "$bunny" -o "$tmp/c.cstree"
check "same input gives the same tree bytes" cmp -s "$tmp/b.cstree" "$tmp/c.cstree"
run -q --threads 1 reconstruct "$bunny" -o "$tmp/d.cstree"
check "one thread gives the same tree bytes" cmp -s "$tmp/b.cstree" "$tmp/d.cstree"
run --json info "$tmp/b.cstree"
expect_contains "crease leaves are on by default" "$out" '"creases": true'
run -q reconstruct "$bunny" -o "$tmp/nc.cstree" --no-creases
run --json info "$tmp/nc.cstree"
expect_contains "--no-creases is stored in the tree" "$out" '"creases": false'
expect_contains "--no-creases: no crease leaf" "$out" '"crease": 0'
run --json mesh "$tmp/b.cstree" -o "$tmp/m2.obj" --resolution 64
expect_rc "mesh exits 0" 0
tris=$(json_field triangles)
if [ -n "$tris" ] && [ "$tris" -gt 1000 ]; then ok "mesh --json reports triangles ($tris)"; else not_ok "mesh --json triangles" "$out"; fi
# --resolution auto: cells two median point spacings wide (the spacing `stats` reports), finer
# (down to one spacing) where the leaves are curved more than that resolves.
run --json stats "$bunny"
spacing=$(json_field median_spacing)
run --json mesh "$tmp/b.cstree" -o "$tmp/m3.ply" --resolution auto --points "$bunny"
expect_rc "mesh --resolution auto exits 0" 0
voxel=$(json_field voxel_size)
if awk -v v="$voxel" -v s="$spacing" 'BEGIN { exit !(s > 0 && v <= 2 * s * (1 + 1e-9) && v >= s * (1 - 1e-9)) }'; then
  ok "mesh --resolution auto: voxel size within 1-2 x median spacing ($voxel, spacing $spacing)"
else
  not_ok "mesh --resolution auto voxel size" "voxel '$voxel', median spacing '$spacing'"
fi
# Tree files (version 2) store the input's median spacing: auto needs no --points.
run --json mesh "$tmp/b.cstree" -o "$tmp/m4.ply" --resolution auto
expect_rc "mesh --resolution auto without --points exits 0" 0
expect_eq "mesh --resolution auto without --points: the voxel from the stored spacing" "$(json_field voxel_size)" "$voxel"
run -q mesh "$tmp/b.cstree" -o "$tmp/m5.ply" --resolution auto --voxel-size 0.5
run --json info "$tmp/b.cstree"
expect_eq "info reports the stored spacing (as stats measures it)" "$(json_field point_spacing)" "$spacing"
# The default is auto, with or without the points.
run -q mesh "$tmp/b.cstree" -o "$tmp/m6.ply" --points "$bunny"
check "mesh --points by default meshes as --resolution auto" cmp -s "$tmp/m3.ply" "$tmp/m6.ply"
run -q reconstruct "$bunny" --mesh "$tmp/m7.ply" --resolution auto
check "reconstruct --mesh by default meshes as --resolution auto" cmp -s "$tmp/m.ply" "$tmp/m7.ply"
run -q mesh "$tmp/b.cstree" -o "$tmp/m8.ply" --resolution auto
check "mesh without --points by default meshes as --resolution auto" cmp -s "$tmp/m4.ply" "$tmp/m8.ply"
# Points that are not the tree's input are refused, never silently used.
run mesh "$tmp/b.cstree" -o "$tmp/m9.ply" --points "$testdata/bunny400.ply"
expect_rc "mesh --points of another cloud: exit code 2" 2
expect_contains "mesh --points of another cloud: the message says so" "$err" "are not the tree's input (1839 points)"
check "mesh --points of another cloud writes nothing" test ! -e "$tmp/m9.ply"
# A version-1 tree file (no stored spacing) still loads and meshes: auto from its points, or
# the fixed cell count without them.
run --json mesh "$testdata/bunny400_v1.cstree" -o "$tmp/v1.ply" --points "$testdata/bunny400.ply"
expect_rc "mesh of a version-1 tree exits 0" 0
voxel_v1=$(json_field voxel_size)
run --json stats "$testdata/bunny400.ply"
spacing_v1=$(json_field median_spacing)
if awk -v v="$voxel_v1" -v s="$spacing_v1" 'BEGIN { exit !(s > 0 && v <= 2 * s * (1 + 1e-9) && v >= s * (1 - 1e-9)) }'; then
  ok "a version-1 tree meshes on the automatic grid of its points ($voxel_v1, spacing $spacing_v1)"
else
  not_ok "a version-1 tree meshes on the automatic grid of its points" "voxel '$voxel_v1', median spacing '$spacing_v1'"
fi
run --json mesh "$testdata/bunny400_v1.cstree" -o "$tmp/v1b.ply"
expect_rc "mesh of a version-1 tree without --points exits 0" 0
run mesh "$tmp/b.cstree" -o "$tmp/m4.ply" --resolution fine
expect_rc "mesh --resolution fine: exit code 2" 2
head -c 100 "$tmp/b.cstree" >"$tmp/trunc.cstree"
run info "$tmp/trunc.cstree"
expect_rc "truncated tree file: exit code 3" 3
expect_contains "truncated tree file: the message names the file" "$err" "$tmp/trunc.cstree"
run reconstruct "$bunny" -o "$tmp/x.cstree" --alpha -1
if [ "$rc" -ne 0 ] && [ ! -e "$tmp/x.cstree" ]; then ok "invalid option is rejected, no output"; else not_ok "invalid option" "rc $rc"; fi
run reconstruct "$bad" -o "$tmp/out/bad.cstree"
expect_rc "reconstruct of a malformed file: exit code 3" 3
no_new_files "reconstruct of a malformed file leaves no output" "$tmp/out" "existing.ply"
if compgen -G "$tmp/.*.tmp*" >/dev/null || compgen -G "$tmp/out/.*.tmp*" >/dev/null; then
  not_ok "no temporary files left anywhere" "$(ls -A "$tmp" "$tmp/out")"
else
  ok "no temporary files left anywhere"
fi

# --- sample and eval ---------------------------------------------------------------------------
run --json sample "$bunny_mesh" -o "$tmp/sampled.ply" -n 5000 --seed 3
expect_rc "sample exits 0" 0
expect_eq "sample writes N points" "$(count "$tmp/sampled.ply")" 5000
run -q sample "$bunny_mesh" -o "$tmp/sampled2.ply" -n 5000 --seed 3
check "sample with the same seed gives the same bytes" cmp -s "$tmp/sampled.ply" "$tmp/sampled2.ply"
run sample "$bunny_mesh" -o "$tmp/sampled3.ply" -n 5000 --noise -1
expect_rc "sample --noise -1 is a usage error" 2
run sample "$tmp/sampled.ply" -o "$tmp/sampled4.ply"
expect_rc "sample of a cloud without faces: exit code 3" 3
expect_contains "sample of a cloud names the file" "$err" "$tmp/sampled.ply"
check "failed sample leaves no output" test ! -e "$tmp/sampled4.ply"
# The virtual range scanner: about N points over the scans, reproducible, then reconstructed.
run --json sample "$bunny_mesh" -o "$tmp/scanned.ply" -n 20000 --scanner 6 --noise 0.0005 --registration 0.0002
expect_rc "sample --scanner exits 0" 0
scanned=$(count "$tmp/scanned.ply")
if [ "$scanned" -gt 14000 ] && [ "$scanned" -lt 26000 ]; then ok "sample --scanner 6 -n 20000 writes about 20000 points ($scanned)"; else not_ok "sample --scanner count" "$scanned"; fi
run -q sample "$bunny_mesh" -o "$tmp/scanned2.ply" -n 20000 --scanner 6 --noise 0.0005 --registration 0.0002
check "sample --scanner with the same seed gives the same bytes" cmp -s "$tmp/scanned.ply" "$tmp/scanned2.ply"
run sample "$bunny_mesh" -o "$tmp/scanned3.ply" --scanner 6 --outliers 0.01
expect_rc "sample --scanner with --outliers is an option error" 2
check "sample --scanner --outliers writes nothing" test ! -e "$tmp/scanned3.ply"
run sample "$bunny_mesh" -o "$tmp/scanned4.ply" --noise 0.001 --noise-correlation 2
expect_rc "sample --noise-correlation without --scanner is an option error" 2
check "sample --noise-correlation without --scanner writes nothing" test ! -e "$tmp/scanned4.ply"
run --json reconstruct "$tmp/scanned.ply" --mesh "$tmp/scanned-mesh.ply"
expect_rc "reconstruct of a virtual scan exits 0" 0
run --json reconstruct "$tmp/scanned.ply" --mesh "$tmp/scanned-closed.ply" --close-pinholes
expect_rc "reconstruct --close-pinholes exits 0" 0
closed=$(python3 -c 'import json,sys; print(json.load(sys.stdin)["mesh"]["closed_pinholes"])' <<<"$out" 2>/dev/null || echo "")
if [ -n "$closed" ] && [ "$closed" -ge 0 ]; then ok "reconstruct --close-pinholes reports the pinholes it closed ($closed)"; else not_ok "closed_pinholes in --json" "$out"; fi
run --json eval "$tmp/scanned-mesh.ply" --reference "$bunny_mesh" --samples 20000
chamfer=$(json_field chamfer)
if awk -v c="$chamfer" 'BEGIN { exit !(c > 0 && c < 0.005) }'; then ok "virtual scan reconstructed within 0.5 % of the diagonal (Chamfer $chamfer)"; else not_ok "virtual scan reconstruction" "$out"; fi
run --json eval "$bunny_mesh" --reference "$bunny_mesh" --samples 20000
expect_rc "eval of a mesh against itself exits 0" 0
chamfer=$(json_field chamfer)
if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1e-9 else 1)" "$chamfer"; then
  ok "eval: a mesh against itself has chamfer 0 ($chamfer)"
else
  not_ok "eval: a mesh against itself has chamfer 0" "$chamfer"
fi
run --json eval "$tmp/sampled.ply" --reference "$bunny_mesh"
expect_rc "eval of a sampled cloud against its mesh exits 0" 0
acc=$(json_field accuracy)
if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1e-6 else 1)" "$acc"; then
  ok "eval: exact samples lie on the mesh (accuracy $acc)"
else
  not_ok "eval: exact samples lie on the mesh" "$acc"
fi
expect_contains "eval --json reports watertightness" "$out" '"watertight": true'
# Outliers: 1 % uniform in the box are left out, and the surface is as if they were not there.
run -q sample "$bunny_mesh" -o "$tmp/outl.ply" -n 20000 --seed 4 --outliers 0.01
run --json reconstruct "$tmp/outl.ply" --mesh "$tmp/outl_mesh.ply"
expect_rc "reconstruct of a cloud with 1 % outliers exits 0" 0
n_out=$(json_field outliers)
if [ -n "$n_out" ] && [ "$n_out" -ge 150 ] && [ "$n_out" -le 260 ]; then ok "reconstruct leaves out the outliers ($n_out of 200)"; else not_ok "reconstruct leaves out about 200 outliers" "$n_out"; fi
run --json eval "$tmp/outl_mesh.ply" --reference "$bunny_mesh" --samples 50000
chamfer=$(json_field chamfer)
if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) < 1.5e-3 else 1)" "$chamfer"; then
  ok "reconstruct with outliers stays on the bunny (chamfer $chamfer)"
else
  not_ok "reconstruct with outliers stays on the bunny (chamfer < 1.5e-3)" "$chamfer"
fi
run eval "$tmp/missing.ply" --reference "$bunny_mesh"
expect_rc "eval of a missing file: exit code 4" 4
# --- render -----------------------------------------------------------------------------------
is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }
run --json render "$tmp/b.cstree" -o "$tmp/r.png" --width 160 --height 120
expect_rc "render exits 0" 0
check "render writes a PNG (magic)" is_png "$tmp/r.png"
rps=$(json_field rays_per_second)
if [ -n "$rps" ] && python3 -c "import sys; sys.exit(0 if float('$rps') > 0 else 1)" 2>/dev/null; then ok "render --json reports rays/s"; else not_ok "render --json rays_per_second" "$out"; fi
for show in clusters spheres proxies; do
  run render "$tmp/b.cstree" -o "$tmp/r-$show.png" --width 96 --height 72 --show "$show"
  expect_rc "render --show $show exits 0" 0
  check "render --show $show writes a PNG" is_png "$tmp/r-$show.png"
done
run render "$tmp/b.cstree" -o "$tmp/r-err.png" --width 96 --height 72 --show error --points "$bunny"
expect_rc "render --show error --points exits 0" 0
run render "$tmp/b.cstree" -o "$tmp/r-hb.png" --width 96 --height 72 --mode hit-blend --highlight 1 --samples 2 --background transparent
expect_rc "render --mode hit-blend --highlight exits 0" 0
run render "$tmp/m.ply" "$bunny_mesh" "$tmp/b.cstree" --grid -o "$tmp/grid.png" --width 96 --height 72
expect_rc "render --grid of a mesh, a cloud and a tree exits 0" 0
check "render --grid writes a PNG" is_png "$tmp/grid.png"
# Inputs far from zero (survey coordinates) are each read relative to their own origin; one
# camera must still frame them all: every picture of the grid shows its input.
"$cli" -q convert "$bunny" "$tmp/near.xyz"
awk '{ $1 += 636000; $2 += 848900; $3 += 400; print }' OFMT='%.9f' CONVFMT='%.9f' "$tmp/near.xyz" >"$tmp/far.xyz"
"$cli" -q reconstruct "$tmp/far.xyz" -o "$tmp/far.cstree" --mesh "$tmp/far.ply"
run --json render "$tmp/far.ply" "$tmp/far.xyz" "$tmp/far.cstree" --grid -o "$tmp/far.png" --width 96 --height 72
hits=$(json_field renders | python3 -c 'import json, sys; print(" ".join(str(r["hits"]) for r in json.load(sys.stdin)))' 2>/dev/null)
if [ "$rc" -eq 0 ] && [ -n "$hits" ] && ! grep -qw 0 <<<"$hits"; then
  ok "render --grid frames a mesh, a cloud and a tree far from zero (hits: $hits)"
else
  not_ok "render --grid of inputs far from zero: every picture shows its input" "rc $rc, hits: $hits"
fi
run render "$tmp/b.cstree" -o "$tmp/out/bad.png" --mode nonsense
expect_rc "render with a bad --mode: exit code 2" 2
run render "$tmp/b.cstree" -o "$tmp/out/bad.png" --show error
expect_rc "render --show error without --points: exit code 2" 2
run render "$tmp/b.cstree" -o "$tmp/out/bad.png" --highlight 999999
expect_rc "render --highlight of a missing node: exit code 2" 2
run render "$tmp/does-not-exist.cstree" -o "$tmp/out/bad.png"
expect_rc "render of a missing input: exit code 4" 4
run render "$tmp/trunc.cstree" -o "$tmp/out/bad.png"
expect_rc "render of a corrupt tree: exit code 3" 3
no_new_files "failed renders leave no output" "$tmp/out" "existing.ply"

# --- view -------------------------------------------------------------------------------------
run --json view "$tmp/b.cstree" -o "$tmp/v.html" --points "$bunny" --mesh "$tmp/m.ply"
expect_rc "view exits 0" 0
expect_eq "view embeds every point" "$(json_field points)" "$(count "$bunny")"
check "view writes one HTML page with the data inside" grep -q 'id="cs-blob-positions"' "$tmp/v.html"
check "the page needs no other file (no src= or href= to files)" bash -c "! grep -Eq '(src|href)=\"[^\"#]' '$tmp/v.html'"
run -q view "$tmp/b.cstree" -o "$tmp/v2.html" --points "$bunny" --mesh "$tmp/m.ply"
check "same inputs give the same page bytes" cmp -s "$tmp/v.html" "$tmp/v2.html"
run --json view "$tmp/b.cstree" -o "$tmp/v-small.html" --points "$bunny" --max-points 1000
expect_eq "view --max-points 1000 embeds 1000 points" "$(json_field points)" 1000
run view "$tmp/b.cstree" -o "$tmp/v-tree.html"
expect_rc "view without --points exits 0" 0
expect_contains "view without --points says the points are not shown" "$err" "--points"
run view "$tmp/b.cstree" -o "$tmp/out/bad.html" --points "$tmp/s1.ply"
expect_rc "view with another cloud: exit code 2" 2
expect_contains "view with another cloud: the message says so" "$err" "are not the tree's input"
run view "$tmp/b.cstree" -o "$tmp/out/bad.png" --points "$bunny"
expect_rc "view to a non-.html file: exit code 2" 2
run view "$tmp/trunc.cstree" -o "$tmp/out/bad.html"
expect_rc "view of a corrupt tree: exit code 3" 3
no_new_files "failed views leave no output" "$tmp/out" "existing.ply"

# --- degenerate geometry: a clear error, or a valid result -------------------------------------
mkdir "$tmp/deg"
for i in $(seq 1 50); do echo "1.5 2.5 3.5"; done >"$tmp/deg/same.xyz"
for i in $(seq 1 50); do echo "$i $((2 * i)) $((3 * i))"; done >"$tmp/deg/line.xyz"
run reconstruct "$tmp/deg/same.xyz" -o "$tmp/deg/same.cstree" --mesh "$tmp/deg/same.ply"
expect_rc "identical points: exit code 3" 3
expect_contains "identical points: message" "$err" "all 50 points coincide: there is no surface to reconstruct"
run reconstruct "$tmp/deg/line.xyz" -o "$tmp/deg/line.cstree"
expect_rc "collinear points: exit code 3" 3
expect_contains "collinear points: message" "$err" "all 50 points lie on one line"
no_new_files "degenerate clouds: no output" "$tmp/deg" "$(printf 'line.xyz\nsame.xyz')"
# The bunny moved to 1e8: meshed as well as where it was.
run convert "$bunny" "$tmp/bunny.xyz"
python3 -c '
import sys
for line in open(sys.argv[1]):
    x, y, z = map(float, line.split()[:3])
    print(f"{x + 1e8:.17g} {y - 1e8:.17g} {z + 1e8:.17g}")' "$tmp/bunny.xyz" >"$tmp/deg/far.xyz" 2>/dev/null
if [ -s "$tmp/deg/far.xyz" ]; then
  run --json reconstruct "$tmp/bunny.xyz" -o "$tmp/deg/near.cstree" --mesh "$tmp/deg/near.ply" --resolution 64
  near_tris=$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["mesh"]["triangles"])' <<<"$out")
  run --json reconstruct "$tmp/deg/far.xyz" -o "$tmp/deg/far.cstree" --mesh "$tmp/deg/far.ply" --resolution 64
  expect_rc "bunny at 1e8: exit code 0" 0
  far_tris=$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["mesh"]["triangles"])' <<<"$out")
  if [ -n "$near_tris" ] && [ -n "$far_tris" ] && [ "$far_tris" -gt $((near_tris * 9 / 10)) ] && [ "$far_tris" -lt $((near_tris * 11 / 10)) ]; then
    ok "bunny at 1e8: as many triangles as at the origin ($far_tris vs $near_tris)"
  else
    not_ok "bunny at 1e8: triangles" "far $far_tris, near $near_tris"
  fi
else
  not_ok "bunny at 1e8: input" "$tmp/bunny.xyz missing"
fi

# --- scanner formats in, mesh formats out ------------------------------------------------------
mkdir "$tmp/fmt"
printf 'LASF' >"$tmp/fmt/a.laz"
run reconstruct "$tmp/fmt/a.laz" -o "$tmp/fmt/a.cstree"
expect_rc "LAZ: exit code 3" 3
expect_contains "LAZ: says it is not supported" "$err" "LAZ (compressed LAS) is not supported"
# Meshes in every output format, decimated on request, back at the data's coordinates.
run --json reconstruct "$bunny" -o "$tmp/fmt/b.cstree" --mesh "$tmp/fmt/b.glb" --decimate 2000
expect_rc "reconstruct --mesh b.glb --decimate 2000: exit code 0" 0
glb_tris=$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["mesh"]["triangles"])' <<<"$out" 2>/dev/null)
if [ -n "$glb_tris" ] && [ "$glb_tris" -le 2000 ] && [ "$glb_tris" -gt 1000 ]; then ok "decimated to $glb_tris triangles"; else not_ok "decimate 2000" "$glb_tris"; fi
expect_eq "GLB magic" "$(head -c 4 "$tmp/fmt/b.glb")" "glTF"
for ext in stl off; do
  run mesh "$tmp/fmt/b.cstree" -o "$tmp/fmt/b.$ext"
  expect_rc "mesh -o b.$ext: exit code 0" 0
done
expect_eq "binary STL: 84 + 50 bytes per triangle" "$((($(stat -c %s "$tmp/fmt/b.stl") - 84) % 50))" 0
expect_eq "OFF header" "$(head -n1 "$tmp/fmt/b.off")" "OFF"
# Closed meshes on request: no boundary edge, the fill marked in the PLY, --fill-holes honoured.
run --json mesh "$tmp/fmt/b.cstree" -o "$tmp/fmt/closed.ply" --points "$bunny" --watertight
expect_rc "mesh --watertight: exit code 0" 0
expect_eq "mesh --watertight: watertight" "$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["watertight"])' <<<"$out" 2>/dev/null)" "True"
expect_eq "mesh --watertight: no boundary edge" "$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["boundary_edges"])' <<<"$out" 2>/dev/null)" 0
expect_contains "mesh --watertight: the filled vertices are a PLY property" "$(head -c 400 "$tmp/fmt/closed.ply")" "property float filled"
run --json mesh "$tmp/fmt/b.cstree" -o "$tmp/fmt/small.ply" --points "$bunny" --watertight --fill-holes 0.000001
filled_open=$(python3 -c 'import json,sys; print(json.loads(sys.stdin.read())["opened_holes"])' <<<"$out" 2>/dev/null)
if [ -n "$filled_open" ] && [ "$filled_open" -gt 0 ]; then ok "--fill-holes: larger holes left open ($filled_open)"; else not_ok "--fill-holes" "$out"; fi
# A grid no machine holds (some 10^9 surface cells of the bunny) is refused before the walk, saying why.
run mesh "$tmp/fmt/b.cstree" -o "$tmp/fmt/huge.ply" --resolution 100000
expect_rc "mesh on a grid beyond the free memory: option error" 2
expect_contains "mesh beyond the free memory: the message names the estimate" "$err" "GiB"
if [ ! -e "$tmp/fmt/huge.ply" ]; then ok "mesh beyond the free memory: nothing written"; else not_ok "mesh beyond the free memory wrote a file"; fi
if [ -n "$shared" ] && [ -f "$shared/formats/las/4_6_crop.las" ]; then
  las="$shared/formats/las/4_6_crop.las"
  run --json stats "$las"
  expect_eq "LAS: 23875 points" "$(json_field points)" 23875
  las_box="$(json_field bbox_min) $(json_field bbox_max)"
  expect_contains "LAS: intensity and classification kept" "$(json_field attributes)" "classification"
  run --json reconstruct "$las" -o "$tmp/fmt/las.cstree" --mesh "$tmp/fmt/las.ply"
  expect_rc "LAS: reconstruct and mesh" 0
  run --json stats "$tmp/fmt/las.ply"
  mesh_box="$(json_field bbox_min) $(json_field bbox_max)"
  # The mesh is written back in the file's projected coordinates (not about the origin the
  # reader shifted them to), within a tenth of the tile's 200 units of the data.
  if python3 -c '
import json, sys
a = [v for part in sys.argv[1].split("] [") for v in json.loads("[" + part.strip("[] ") + "]")]
b = [v for part in sys.argv[2].split("] [") for v in json.loads("[" + part.strip("[] ") + "]")]
sys.exit(0 if a[0] > 1e5 and all(abs(x - y) < 20 for x, y in zip(a, b)) else 1)' "$las_box" "$mesh_box"; then
    ok "LAS: the mesh is back at the data's coordinates ($mesh_box)"
  else
    not_ok "LAS: mesh coordinates" "data $las_box, mesh $mesh_box"
  fi
  run --json stats "$shared/formats/ptx/multiple-and-transform.ptx"
  expect_eq "PTX: two scanners" "$(json_field scanners)" 2
  # The aerial tile's RGB goes onto the mesh, in core and out of core; --color none leaves it off.
  # 15,000 of its 110,000 points (their colors and up axis kept) make the three runs cheap.
  tile="$tmp/fmt/tile_points.ply"
  run convert --subsample 15000 "$shared/formats/las/autzen_trim.las" "$tile"
  expect_rc "LAS with RGB: 15,000 of its points converted" 0
  run reconstruct "$tile" --mesh "$tmp/fmt/tile.ply"
  run --json stats "$tmp/fmt/tile.ply"
  expect_eq "LAS with RGB: the mesh has the scan's colors" "$(json_field has_colors)" true
  run --json reconstruct "$tile" --mesh "$tmp/fmt/tile_ooc.ply" --memory-limit 200M --work-dir "$tmp/fmt/tile_work"
  expect_eq "LAS with RGB under a 200M limit: meshed tile by tile" "$(python3 -c 'import json,sys; print(json.load(sys.stdin)["mesh"]["streamed"])' <<<"$out" 2>/dev/null)" "True"
  run --json stats "$tmp/fmt/tile_ooc.ply"
  expect_eq "LAS with RGB out of core: the mesh has the scan's colors" "$(json_field has_colors)" true
  run reconstruct "$tile" --mesh "$tmp/fmt/tile_plain.ply" --color none
  run --json stats "$tmp/fmt/tile_plain.ply"
  expect_eq "--color none: no colors" "$(json_field has_colors)" false
  # A survey's cloud and its mesh are pictured z-up by default (the mesh file says "comment up z").
  run render "$shared/formats/las/autzen_trim.las" -o "$tmp/fmt/tile_points.png"
  expect_rc "render of a LAS cloud" 0
  if grep -q "^comment up z" "$tmp/fmt/las.ply"; then ok "the mesh of a LAS input is written z-up"; else not_ok "the mesh of a LAS input is not marked z-up"; fi
  run stats "$shared/formats/las/bad_vlr_count.las"
  expect_rc "LAS with a broken VLR count: exit code 3" 3
  expect_contains "LAS with a broken VLR count: byte offset" "$err" "bad_vlr_count.las: byte 429: "
else
  echo "skip - shared format samples not found in '${shared}': LAS/PTX checks skipped"
fi

# --- check: is a mesh ready to print ------------------------------------------------------------
run check "$bunny_mesh"
expect_rc "check of a closed mesh exits 0" 0
expect_contains "check: the closed bunny is printable" "$out" "printable       yes"
run --json check "$bunny_mesh"
expect_eq "check --json: the bunny is watertight" "$(json_field watertight)" true
expect_eq "check --json: the bunny has genus 0" "$(json_field genus)" 0
expect_eq "check --json: the bunny does not intersect itself" "$(json_field self_intersections)" 0
if python3 -c "import sys; sys.exit(0 if float(sys.argv[1]) > 0 else 1)" "$(json_field volume)" 2>/dev/null; then
  ok "check --json: the bunny encloses a positive volume"
else
  not_ok "check --json: volume" "$out"
fi
# The mesh reconstruct wrote from the bunny (open where the data stops): a report, exit code 0.
run --json check "$tmp/m.ply"
expect_rc "check of a reconstructed mesh exits 0 whether printable or not" 0
missing=""
for field in vertices triangles boundary_edges non_manifold_edges inconsistent_edges components euler_characteristic \
  genus volume self_intersections watertight consistently_oriented printable problems; do
  [[ "$out" == *"\"$field\":"* ]] || missing="$missing $field"
done
expect_eq "check --json reports every field" "$missing" ""
expect_eq "check: the reconstructed mesh does not intersect itself" "$(json_field self_intersections)" 0
# One triangle pushed through another: one intersecting pair, not printable, still exit code 0.
printf 'ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n0 2 0\n0.4 0.4 -1\n0.6 0.4 1\n0.5 0.6 1\n3 0 1 2\n3 3 4 5\n' >"$tmp/pierced.ply"
run check "$tmp/pierced.ply"
expect_rc "check of a self-intersecting mesh exits 0" 0
expect_contains "check names the intersecting pair" "$out" "self-intersect  1 triangle pair (triangles 0&1)"
expect_contains "check says why it is not printable" "$out" "printable       no: 6 boundary edges, 1 self-intersecting triangle pair"
run check "$testdata/bunny400.ply"
expect_rc "check of a cloud without faces: exit code 3" 3
run check "$tmp/missing.ply"
expect_rc "check of a missing file: exit code 4" 4

# --- interrupt (SIGINT): no output, a clear message, existing files untouched -------------------
big="$tmp/big.ply"
run sample "$bunny_mesh" -o "$big" -n 2000000 --seed 3
expect_rc "sample a large cloud for the interrupt test" 0
mkdir "$tmp/int"
printf 'a good tree\n' >"$tmp/int/keep.cstree"
before=$(cksum <"$tmp/int/keep.cstree")
"$cli" reconstruct "$big" -o "$tmp/int/keep.cstree" --mesh "$tmp/int/new.ply" >"$tmp/stdout" 2>"$tmp/stderr" &
pid=$!
sleep 2
kill -INT "$pid"
wait "$pid"
rc=$?
err=$(cat "$tmp/stderr")
expect_rc "SIGINT during reconstruct: exit code 130" 130
expect_contains "SIGINT: the message says so" "$err" "interrupted: stopped before writing any output"
expect_eq "SIGINT: the existing tree file is untouched" "$(cksum <"$tmp/int/keep.cstree")" "$before"
no_new_files "SIGINT: no mesh, no temporary file" "$tmp/int" "keep.cstree"

# --- out of core ---------------------------------------------------------------------------------
ooc="$tmp/ooc"
mkdir "$ooc"
# 60,000 points: two regions and two tiles within the smallest limit, so seams, the merge and a
# resume are exercised at a size the sanitized build runs in seconds.
run sample "$bunny_mesh" -o "$ooc/in.ply" -n 60000 --seed 5
expect_rc "sample a cloud for the out-of-core run" 0
run --json reconstruct "$ooc/in.ply" --mesh "$ooc/mesh.ply" --memory-limit 128M
expect_rc "reconstruct --memory-limit exits 0" 0
expect_eq "out of core: the mesh is written tile by tile" "$(python3 -c 'import json,sys; print(json.load(sys.stdin)["mesh"]["streamed"])' <<<"$out")" "True"
check "out of core: the work directory is removed" test ! -e "$ooc/mesh.ply.work"
run reconstruct "$ooc/in.ply" --mesh "$ooc/again.ply" --memory-limit 128M --work-dir "$ooc/work" --keep-work-dir
expect_rc "reconstruct --memory-limit --keep-work-dir exits 0" 0
check "out of core: --keep-work-dir keeps the run's files" test -f "$ooc/work/plan.txt"
check "out of core: the cloud was split into regions" test -f "$ooc/work/region-000001.own"
check "out of core: the same mesh from a kept work directory" cmp -s "$ooc/mesh.ply" "$ooc/again.ply"
rm -f "$ooc/work/tile-000000.bin"  # as if the run had stopped before this tile
run reconstruct "$ooc/in.ply" --mesh "$ooc/resumed.ply" --memory-limit 128M --work-dir "$ooc/work"
expect_rc "a resumed out-of-core run exits 0" 0
check "out of core: the resumed run gives the same mesh" cmp -s "$ooc/mesh.ply" "$ooc/resumed.ply"
# A full disk, as a 1 MB file-size limit (a region file is larger; SIGXFSZ ignored, so a write
# past it fails with EFBIG): a clear I/O error and no mesh.
(ulimit -f 1024; trap '' XFSZ; exec "$cli" reconstruct "$ooc/in.ply" --mesh "$ooc/full.ply" --memory-limit 128M \
  --work-dir "$ooc/full") >"$tmp/stdout" 2>"$tmp/stderr"
rc=$?
err=$(cat "$tmp/stderr")
expect_rc "out of core, disk full: I/O error" 4
expect_contains "out of core, disk full: the message names the failed write" "$err" "write failed"
check "out of core, disk full: no mesh" test ! -e "$ooc/full.ply"
rm -rf "$ooc/full"
# A work directory of the user's: used alongside their files, which are never touched; only the
# run's own files are removed, and the directory is kept (the run did not create it).
mkdir "$tmp/precious"
printf 'my thesis\n' >"$tmp/precious/thesis.txt"
printf 'my notes\n' >"$tmp/precious/.notes.txt.tmp123456"
run reconstruct "$ooc/in.ply" --mesh "$ooc/user.ply" --memory-limit 128M --work-dir "$tmp/precious"
expect_rc "out of core in the user's directory exits 0" 0
check "out of core in the user's directory: the same mesh" cmp -s "$ooc/mesh.ply" "$ooc/user.ply"
no_new_files "out of core in the user's directory: their files are kept, the run's removed" "$tmp/precious" ".notes.txt.tmp123456
thesis.txt"
# Failing half way (a full disk) and interrupted (SIGINT): the user's files are still there.
(ulimit -f 1024; trap '' XFSZ; exec "$cli" reconstruct "$ooc/in.ply" --mesh "$ooc/full.ply" --memory-limit 128M \
  --work-dir "$tmp/precious") >"$tmp/stdout" 2>"$tmp/stderr"
rc=$?
err=$(cat "$tmp/stderr")
expect_rc "out of core in the user's directory, disk full: I/O error" 4
check "out of core in the user's directory, disk full: their file is kept" grep -q "my thesis" "$tmp/precious/thesis.txt"
"$cli" reconstruct "$big" --mesh "$ooc/int.ply" --memory-limit 128M --work-dir "$tmp/precious" >"$tmp/stdout" 2>"$tmp/stderr" &
pid=$!
sleep 3
kill -INT "$pid"
wait "$pid"
rc=$?
err=$(cat "$tmp/stderr")
expect_rc "out of core in the user's directory, SIGINT: exit code 130" 130
check "out of core in the user's directory, SIGINT: their file is kept" grep -q "my thesis" "$tmp/precious/thesis.txt"
check "out of core in the user's directory, SIGINT: no mesh" test ! -e "$ooc/int.ply"
# A work directory that is a file, or that holds a file named like a run's: refused before any work.
printf 'not a directory\n' >"$tmp/afile"
run reconstruct "$ooc/in.ply" --mesh "$ooc/bad.ply" --memory-limit 128M --work-dir "$tmp/afile"
expect_rc "a work directory that is a file: usage error" 2
expect_contains "a work directory that is a file: the message says so" "$err" "is not a directory"
expect_eq "a work directory that is a file: the file is untouched" "$(cat "$tmp/afile")" "not a directory"
mkdir "$tmp/foreign"
printf 'my plan\n' >"$tmp/foreign/plan.txt"
run reconstruct "$ooc/in.ply" --mesh "$ooc/bad.ply" --memory-limit 128M --work-dir "$tmp/foreign"
expect_rc "a work directory holding another plan.txt: usage error" 2
expect_contains "a work directory holding another plan.txt: the message names it" "$err" "holds plan.txt"
no_new_files "a work directory holding another plan.txt: nothing written" "$tmp/foreign" "plan.txt"
run reconstruct "$ooc/in.ply" --mesh "$ooc/bad.ply" --memory-limit 4X
expect_rc "--memory-limit 4X: usage error" 2
expect_contains "--memory-limit 4X: the message says what a size is" "$err" "a memory size is a number"
run reconstruct "$ooc/missing.ply" --mesh "$ooc/bad.ply" --memory-limit 1G
expect_rc "out of core, missing input: I/O error" 4
# The resumed run, done, removed its work directory; the failed ones made nothing.
no_new_files "out of core: failed runs leave nothing" "$ooc" "again.ply
in.ply
mesh.ply
resumed.ply
user.ply"

# --- shared data (optional) ---------------------------------------------------------------------
if [ -n "$shared" ] && [ -f "$shared/bunny/scans/bun000.ply" ]; then
  expect_eq "shared bun000.ply has 40256 points" "$(count "$shared/bunny/scans/bun000.ply")" 40256
  run --json convert --voxel 0.002 "$shared/bunny/scans/bun000.ply" "$tmp/scan.ply"
  expect_rc "voxel-downsampling a real scan" 0
else
  echo "skip - shared data not found in '${shared}': real-scan checks skipped"
fi

echo
echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
