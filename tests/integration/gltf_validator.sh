#!/usr/bin/env bash
# tests/integration/gltf_validator.sh — every kind of GLB lumesh writes passes the Khronos
# glTF-Validator (npm gltf-validator, installed by scripts/install-deps.sh from
# tests/support/gltf) with no error and no warning: gen-frog's textured multi-part model, simplify
# (qem, image, adaptive, from an OBJ with its texture, from an OBJ with a normal map (normalTexture
# and TANGENT), from the assimp duck (Collada, textured), with --cull-unseen), optimize (also
# --bake normal: through a hill grid's own UVs, and through the packed chart atlas with gen-frog's
# texture resampled; --bake color and --bake normal,color on the textured gen-frog (baseColorTexture
# baked) and the duck), lod one file per level and --msft-lod, pm-extract. Every model is
# converted with its texture beside it. Exits 77 (skipped, with the reason) without Node.js or
# the package.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
source "$here/bake_grid.bash"
root=$(cd "$here/../.." && pwd)
npmdir=${LUMESH_TEST_DATA:-$root/tests/data}/cache/npm-gltf
skip() {
  echo "SKIP: gltf_validator.sh: $*"
  exit 77
}
command -v node >/dev/null || skip "no node (Node.js: scripts/install-deps.sh)"
[ -e "$npmdir/node_modules/gltf-validator/package.json" ] ||
  skip "no gltf-validator under $npmdir (scripts/install-deps.sh)"

scratch
# validate.mjs finds its package beside it
cp "$root/tests/support/gltf/validate.mjs" "$tmp/validate.mjs"
ln -s "$npmdir/node_modules" "$tmp/node_modules"
small=(--views 4 --size 32 --device host)

expect_exit 0 "$LUMESH" gen-frog -o "$tmp/frog.glb" --tris 1500 --seed 3
expect_exit 0 "$LUMESH" gen-frog -o "$tmp/obj/frog.obj" --tris 1500 --seed 3
expect_exit 0 "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/out/qem.glb" --target-verts 150
expect_exit 0 "$LUMESH" simplify "$tmp/obj/frog.obj" -o "$tmp/out/from_obj.glb" --target-verts 150
# a normal-mapped model (the frog's texture as its MTL's "norm" map): normalTexture and TANGENT
mkdir -p "$tmp/nrm"
cp "$tmp"/obj/frog_*.png "$tmp/nrm/"
sed 's/^map_Kd \(.*\)$/map_Kd \1\nnorm \1/' "$tmp/obj/frog.mtl" >"$tmp/nrm/frog.mtl"
cp "$tmp/obj/frog.obj" "$tmp/nrm/frog.obj"
expect_exit 0 "$LUMESH" simplify "$tmp/nrm/frog.obj" -o "$tmp/out/normal_mapped.glb" \
  --target-verts 150
checks=$((checks + 1))
grep -aq '"normalTexture"' "$tmp/out/normal_mapped.glb" && grep -aq '"TANGENT"' "$tmp/out/normal_mapped.glb" ||
  fail "normal_mapped.glb has no normalTexture or no TANGENT"
# the exact CPU renderer here: this command with --device host (llvmpipe) crashed twice (SIGSEGV,
# nothing on stderr) on a loaded 2-core machine and never in ~100 runs alone; open, see the issue
# 39 note of 2026-12-06. What this test checks is the GLB, not the renderer.
expect_exit 0 "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/out/image.glb" --target-verts 150 \
  --method image --pm "$tmp/frog.pm" --views 4 --size 32 --device cpu
expect_exit 0 "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/out/adaptive.glb" --target-verts 150 \
  --method adaptive
expect_exit 0 "$LUMESH" pm-extract "$tmp/frog.pm" -o "$tmp/out/pm.glb" --verts 300
expect_exit 0 "$LUMESH" simplify "$tmp/frog.glb" -o "$tmp/out/culled.glb" --target-verts 150 \
  --views upper:4 --size 32 --cull-unseen
expect_exit 0 "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/out/optimized.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}"
expect_exit 0 "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/out/baked_atlas.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake normal --bake-size 256
expect_exit 0 "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/out/baked_color.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake color --bake-size 256
expect_exit 0 "$LUMESH" optimize "$tmp/frog.glb" -o "$tmp/out/baked_both.glb" --target-verts 120 \
  --start qem --evals 300 --seed 1 "${small[@]}" --bake normal,color --bake-size 512
grid 9 0.3 >"$tmp/hill.obj"
grid 3 0.3 >"$tmp/hill3.obj"
expect_exit 0 "$LUMESH" optimize "$tmp/hill.obj" --initial "$tmp/hill3.obj" -o "$tmp/out/baked_uv.glb" \
  --evals 50 --seed 1 "${small[@]}" --bake normal --bake-size 64
expect_exit 0 "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/out/lod.glb" --levels 50%,20% --method qem \
  --no-optimize "${small[@]}"
expect_exit 0 "$LUMESH" lod "$tmp/frog.glb" -o "$tmp/out/msft.glb" --levels 50%,20% --method qem \
  --no-optimize --msft-lod "${small[@]}"
duck=${LUMESH_TEST_DATA:-$root/tests/data}/cache/root/usr/share/assimp/models/Collada/duck.dae
if [ -e "$duck" ]; then
  expect_exit 0 "$LUMESH" simplify "$duck" -o "$tmp/duck/duck.glb" --target-verts 300
  expect_exit 0 "$LUMESH" optimize "$duck" -o "$tmp/duck/duck_baked.glb" --target-verts 300 \
    --start qem --evals 300 --seed 1 "${small[@]}" --bake normal,color --bake-size 512
  cp "$(dirname "$duck")"/duckCM.* "$tmp/duck/" 2>/dev/null
else
  fail "test model missing: $duck (scripts/install-deps.sh fetches it)"
fi

glbs=("$tmp/frog.glb" "$tmp"/out/*.glb "$tmp"/duck/*.glb)
checks=$((checks + 1))
[ "${#glbs[@]}" -ge 18 ] || fail "expected at least 18 GLBs, got ${#glbs[@]}: ${glbs[*]}"
checks=$((checks + 1))
# (without the sanitizer run's LD_PRELOAD: Node.js does not run under the ASan runtime)
env -u LD_PRELOAD node "$tmp/validate.mjs" "${glbs[@]}" >"$tmp/report.txt" 2>&1 ||
  fail "the glTF-Validator found errors or warnings: $(grep -v ' 0 errors, 0 warnings' "$tmp/report.txt" | head -20)"
cat "$tmp/report.txt"
finish
