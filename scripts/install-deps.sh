#!/usr/bin/env bash
# Installs every Debian package lumesh needs to build, test and run (Debian 12; python3 and
# chromium are for the tests: headless Chromium opens the quality report; slurm-wlm and munge
# for the single-node Slurm of tests/integration/slurm.sh; yamllint, Node.js and the npm packages
# of tests/support/k8s for the Kubernetes manifests' check; systemd for systemd-analyze), and
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
# The Kubernetes manifests' schema check (tests/integration/kubernetes.sh): the npm packages of
# tests/support/k8s, at the versions of its lock file.
npmdir="$cache/npm"
if ! cmp -s "$here/tests/support/k8s/package-lock.json" "$npmdir/package-lock.json" ||
  [ ! -e "$npmdir/node_modules/kubernetes-models/package.json" ]; then
  mkdir -p "$npmdir"
  cp "$here/tests/support/k8s/package.json" "$here/tests/support/k8s/package-lock.json" "$npmdir/"
  (cd "$npmdir" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
fi
echo "install-deps: ok"
