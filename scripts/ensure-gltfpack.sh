#!/usr/bin/env bash
# Makes sure gltfpack (meshoptimizer's glTF packer, Debian package gltfpack) is installed: the
# loader's tests make quantized (KHR_mesh_quantization) and meshopt-compressed
# (EXT_meshopt_compression) copies of the shared scenes with it. Needs root or sudo only when it
# has to install.
set -euo pipefail

if command -v gltfpack >/dev/null 2>&1; then
    echo "ensure-gltfpack: $(gltfpack -v 2>/dev/null | head -1 || echo gltfpack) is installed"
    exit 0
fi

echo "ensure-gltfpack: installing gltfpack (Debian package gltfpack)"
SUDO=""
if [ "$(id -u)" != "0" ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
        echo "ensure-gltfpack: not root and no sudo; run as root: apt-get install gltfpack" >&2
        exit 1
    fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq gltfpack >/dev/null
command -v gltfpack >/dev/null 2>&1 || { echo "ensure-gltfpack: the install did not provide gltfpack" >&2; exit 1; }
echo "ensure-gltfpack: installed"
