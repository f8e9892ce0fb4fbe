#!/usr/bin/env bash
# Makes sure a Vulkan device exists: when no Vulkan driver (ICD) is installed, installs Mesa's
# software driver, lavapipe (Debian/Ubuntu package mesa-vulkan-drivers). Needs root or sudo
# only when it has to install.
set -euo pipefail

have_vulkan() {
    local libs
    libs=$(ldconfig -p 2>/dev/null || true)
    case "$libs" in *libvulkan.so.1*) ;; *) return 1 ;; esac
    local f
    for f in /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json; do
        [ -e "$f" ] && return 0
    done
    return 1
}

if have_vulkan; then
    echo "ensure-vulkan: a Vulkan driver is installed"
    exit 0
fi

echo "ensure-vulkan: no Vulkan driver found; installing Mesa's lavapipe (mesa-vulkan-drivers)"
SUDO=""
if [ "$(id -u)" != "0" ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
        echo "ensure-vulkan: not root and no sudo; run as root: apt-get install mesa-vulkan-drivers" >&2
        exit 1
    fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
have_vulkan || { echo "ensure-vulkan: lavapipe did not install a Vulkan driver" >&2; exit 1; }
echo "ensure-vulkan: installed lavapipe"
