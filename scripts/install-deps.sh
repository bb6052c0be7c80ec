#!/usr/bin/env bash
# Installs every Debian package lumesh needs to build, test and run (Debian 12; python3 and
# chromium are for the tests: headless Chromium opens the quality report; slurm-wlm and munge
# for the single-node Slurm of tests/integration/slurm.sh; yamllint, Node.js and the npm packages
# of tests/support/k8s for the Kubernetes manifests' check and of tests/support/gltf for the glTF
# validator; systemd for systemd-analyze), and
# fetches the test models (assimp-testmodels, libcgal-demo) into tests/data/cache without their
# dependencies.
# Idempotent: re-running it only checks. Needs root (or sudo) for apt-get.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive

PKGS=(
  build-essential cmake pkg-config git ca-certificates
  clang libclang-rt-14-dev clang-format
  libegl-dev libgles-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libgbm1
  libopenimageio-dev libusb-1.0-0-dev libassimp-dev libmeshoptimizer-dev libjansson-dev
  libzmq3-dev libprotobuf-c-dev protobuf-c-compiler libsodium-dev libcmocka-dev libsuitesparse-dev
  iproute2
)
# LUMESH_DEPS=build (deploy/Containerfile): only what building and running need; no test tools,
# test models or npm packages.
tests=1
[ "${LUMESH_DEPS:-all}" = build ] && tests=0
if [ "$tests" = 1 ]; then
  PKGS+=(python3 chromium slurm-wlm munge yamllint systemd)
  # Node.js: the machine's own if it has one (a newer one than Debian's), else Debian's.
  command -v node >/dev/null && command -v npm >/dev/null || PKGS+=(nodejs npm)
fi

missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ "$tests" = 0 ]; then
  echo "install-deps: ok (build and run only)"
  exit 0
fi

# Test models: unpack the two data packages without pulling in their (large) dependencies.
cache="$here/tests/data/cache"
mkdir -p "$cache"
fetch_pkg() { # $1 package, $2 file that shows it is already unpacked
  [ -e "$cache/root/$2" ] && return 0
  local tmp
  tmp=$(mktemp -d)
  (cd "$tmp" && apt-get download -qq "$1" >/dev/null 2>&1 || { $SUDO apt-get update -qq && apt-get download -qq "$1"; })
  dpkg-deb -x "$tmp"/"$1"_*.deb "$cache/root"
  rm -rf "$tmp"
}
fetch_pkg assimp-testmodels usr/share/assimp/models/OBJ/spider.obj
fetch_pkg libcgal-demo usr/share/doc/libcgal-dev/data.tar.gz
if [ ! -e "$cache/meshes/bunny00.off" ]; then
  mkdir -p "$cache/meshes"
  tar -xzf "$cache/root/usr/share/doc/libcgal-dev/data.tar.gz" -C "$cache" --wildcards '*/meshes/bunny00.off' '*/meshes/*.off' 2>/dev/null || true
  f=$(find "$cache" -path '*meshes/bunny00.off' | head -1)
  [ -n "$f" ] && [ "$f" != "$cache/meshes/bunny00.off" ] && cp "$f" "$cache/meshes/bunny00.off"
fi
[ -e "$cache/meshes/bunny00.off" ] || { echo "install-deps: could not extract bunny00.off" >&2; exit 1; }
# npm packages of the tests, each at the versions of its lock file: tests/support/$1 installed into
# the cache folder $2 (unless its lock file is there already with package $3).
npm_install() {
  local src="$here/tests/support/$1" dst="$cache/$2"
  if ! cmp -s "$src/package-lock.json" "$dst/package-lock.json" ||
    [ ! -e "$dst/node_modules/$3/package.json" ]; then
    mkdir -p "$dst"
    cp "$src/package.json" "$src/package-lock.json" "$dst/"
    (cd "$dst" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  fi
}
# The Kubernetes manifests' schema check (tests/integration/kubernetes.sh).
npm_install k8s npm kubernetes-models
# The Khronos glTF-Validator for every GLB lumesh writes (tests/integration/gltf_validator.sh).
npm_install gltf npm-gltf gltf-validator
echo "install-deps: ok"
