#!/usr/bin/env bash
# Install test ("relocatable install"): the installed giharness
# needs no source tree.
#
#   tests/install_test.sh BUILD_DIR SOURCE_DIR
#       cmake --install BUILD_DIR into a temporary prefix, then the checks
#       (ctest: InstallTest.*).
#   tests/install_test.sh --installed BINARY SOURCE_DIR
#       the checks on a binary installed otherwise (.ci/deb-check: /usr/bin).
#
# Checks: the binary holds no SOURCE_DIR (strings: no compiled-in path, no
# __FILE__, no debug-info path); every "#include" of the installed GLSL
# resolves inside the installed data folder (shaders the smoke run does not
# compile included); from an empty folder, with GIHARNESS_SOURCE_DIR,
# GIHARNESS_DATA_DIR and GIHARNESS_PROFILE_DIR unset, a 32x18 realtime
# Cornell box with GI (DI, world cache, ReSTIR GI shaders) runs 2 frames, the finite check passes, and the profile it
# loaded lies in the installed tree (as root the source tree is hidden under
# an empty tmpfs for that run); a copy of the binary with no data folder
# beside it, or pointed at a wrong GIHARNESS_DATA_DIR, exits 3 naming where
# it looked. Nothing is copied from SOURCE_DIR.
set -euo pipefail

fail() { echo "install_test: FAIL: $*" >&2; exit 1; }

if [ "${1:-}" = "--installed" ]; then
  [ $# -eq 3 ] || { echo "usage: $0 --installed BINARY SOURCE_DIR" >&2; exit 2; }
  bin=$(readlink -f "$2")
  source_dir=$(cd "$3" && pwd -P)
  work=$(mktemp -d /tmp/giharness-install-test.XXXXXX)
else
  [ $# -eq 2 ] || { echo "usage: $0 BUILD_DIR SOURCE_DIR" >&2; exit 2; }
  source_dir=$(cd "$2" && pwd -P)
  work=$(mktemp -d /tmp/giharness-install-test.XXXXXX)
  cmake --install "$1" --prefix "$work/prefix" > "$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }
  bin="$work/prefix/bin/giharness"
fi
trap 'rm -rf "$work"' EXIT
prefix=$(dirname "$(dirname "$bin")")
data="$prefix/share/giharness"
[ -x "$bin" ] || fail "no executable $bin"
for f in gpu/shaders/primary_visibility.comp core/shared/brdf.h scenarios/profiles/solari-0.18.json \
         scenarios/schema.json scenarios/assets/glossy_room.gltf reports/baselines; do
  [ -e "$data/$f" ] || fail "$data/$f was not installed"
done
[ ! -L "$data/gpu/shaders" ] || fail "$data/gpu/shaders is a symlink (into the source tree?)"

# 1. No source path anywhere in the binary.
if hits=$(strings -a "$bin" | grep -F "$source_dir"); then
  echo "$hits" | head -5 >&2
  fail "$bin holds the source path $source_dir ($(echo "$hits" | wc -l) strings)"
fi
echo "strings: no '$source_dir' in $bin"

# 2. Every quoted include of the installed GLSL resolves in the data folder,
#    relative to the includer or to the folder (gpu/shader_compiler.cpp).
missing=0
while IFS= read -r file; do
  while IFS= read -r inc; do
    [ -f "$(dirname "$file")/$inc" ] || [ -f "$data/$inc" ] || { echo "unresolved: $file includes $inc" >&2; missing=1; }
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$file")
done < <(find "$data/gpu" "$data/core" -type f)
[ $missing -eq 0 ] || fail "the installed GLSL includes files that were not installed (CMakeLists.txt GIHARNESS_DATA)"

# 3. A realtime run from an empty folder, no variable pointing anywhere.
mkdir -p "$work/empty"
cat > "$work/smoke.json" <<'EOF'
{
  "name": "install_smoke",
  "description": "tests/install_test.sh: the installed binary runs the realtime pipeline with GI (profile, shaders) from its own data folder.",
  "scene": {"generator": "cornell_box"},
  "resolution": [32, 18],
  "frames": 2,
  "seed": 1,
  "profile": "solari-0.18",
  "mode": "realtime",
  "gi": true,
  "checks": [{"name": "finite"}]
}
EOF
clean_env=(env -u GIHARNESS_SOURCE_DIR -u GIHARNESS_DATA_DIR -u GIHARNESS_PROFILE_DIR)
# Where allowed (root), the source tree is really gone for this run: an empty
# tmpfs over it in a private mount namespace, which no other process sees.
hide=()
case "$bin/ $work/" in
  *"$source_dir/"*) ;;  # the binary or the scratch folder lies inside it: cannot hide
  *) if unshare -m true 2> /dev/null; then
       hide=(unshare -m sh -c 'mount -t tmpfs none "$0" && exec "$@"' "$source_dir")
     fi ;;
esac
if [ ${#hide[@]} -gt 0 ] && [ -z "$("${hide[@]}" ls -A "$source_dir")" ]; then
  tree="hidden under an empty tmpfs"
else
  hide=(); tree="visible (no mount namespace here; the strings check stands alone)"
fi
rc=0
(cd "$work/empty" && "${hide[@]}" "${clean_env[@]}" "$bin" run "$work/smoke.json" --out "$work/out") > "$work/run.log" 2>&1 || rc=$?
[ $rc -eq 0 ] || { tail -20 "$work/run.log" >&2; fail "the installed binary's run exited $rc"; }
# Exit 0 means every check passed; make sure the finite check was one.
grep -q '"name": *"finite"' "$work/out/summary.json" || fail "no finite check in $work/out/summary.json"
profile=$(grep -o '"file": *"[^"]*solari-0.18.json"' "$work/out/summary.json" | head -1 | sed 's/.*: *"//; s/"$//')
case "$profile" in
  "$data"/*) echo "run: exit 0, profile read from $profile, source tree $tree" ;;
  *) fail "the run read its profile from '$profile', not from $data" ;;
esac

# 4. Without its data folder the binary stops with exit 3 and says where it looked.
mkdir -p "$work/lonely/bin"
cp "$bin" "$work/lonely/bin/giharness"
rc=0
(cd "$work/empty" && "${clean_env[@]}" "$work/lonely/bin/giharness" run "$work/smoke.json" --out "$work/out2") > "$work/lonely.log" 2>&1 || rc=$?
[ $rc -eq 3 ] && grep -q "tried $work/lonely/share/giharness" "$work/lonely.log" ||
  { cat "$work/lonely.log" >&2; fail "a binary without data exited $rc, expected 3 naming $work/lonely/share/giharness"; }
rc=0
(cd "$work/empty" && GIHARNESS_DATA_DIR="$work/nowhere" "$bin" run "$work/smoke.json" --out "$work/out3") > "$work/wrong.log" 2>&1 || rc=$?
[ $rc -eq 3 ] && grep -q "GIHARNESS_DATA_DIR=$work/nowhere" "$work/wrong.log" ||
  { cat "$work/wrong.log" >&2; fail "a wrong GIHARNESS_DATA_DIR exited $rc, expected 3 naming it"; }
echo "without data: exit 3 with the places tried"
echo "install_test: PASS ($bin)"
