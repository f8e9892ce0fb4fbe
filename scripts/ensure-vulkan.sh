#!/usr/bin/env bash
# Makes sure a Vulkan device exists: when no Vulkan driver (ICD) is installed, installs Mesa's
# software driver, lavapipe (Debian/Ubuntu package mesa-vulkan-drivers). Needs root or sudo
# only when it has to install.
#
# Lavapipe implements VK_KHR_acceleration_structure and VK_KHR_ray_query (wgpu's
# EXPERIMENTAL_RAY_QUERY) from Mesa 24.1 on. Where the installed lavapipe is older and the
# distribution offers a newer one in its backports suite (Debian 12: bookworm-backports carries
# Mesa 25.0), this script installs that one, so the hardware ray-query path can run on a machine
# without a GPU. It says which Mesa it ended with. Elsewhere (another distribution, no apt, a
# hardware driver) it leaves the driver as it is.
set -euo pipefail

# Mesa's first version with ray queries in lavapipe.
RAY_QUERY_MESA="24.1"

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

# The installed mesa-vulkan-drivers version ("" when dpkg does not know it).
mesa_version() {
    dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true
}

SUDO=""
need_root() {
    if [ "$(id -u)" != "0" ]; then
        if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
            echo "ensure-vulkan: not root and no sudo; run as root: $1" >&2
            exit 1
        fi
    fi
}
export DEBIAN_FRONTEND=noninteractive

if have_vulkan; then
    echo "ensure-vulkan: a Vulkan driver is installed"
else
    echo "ensure-vulkan: no Vulkan driver found; installing Mesa's lavapipe (mesa-vulkan-drivers)"
    need_root "apt-get install mesa-vulkan-drivers"
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq mesa-vulkan-drivers libvulkan1 >/dev/null
    have_vulkan || { echo "ensure-vulkan: lavapipe did not install a Vulkan driver" >&2; exit 1; }
    echo "ensure-vulkan: installed lavapipe"
fi

version=$(mesa_version)
if [ -z "$version" ]; then
    echo "ensure-vulkan: Mesa's Vulkan drivers are not a dpkg package here; left as they are"
    exit 0
fi
# "25.0.7-2~bpo12+1" -> "25.0.7"; compared as versions.
upstream=${version%%-*}
if dpkg --compare-versions "$upstream" ge "$RAY_QUERY_MESA"; then
    echo "ensure-vulkan: Mesa $version (lavapipe has ray queries)"
    exit 0
fi
codename=""
if [ -r /etc/os-release ]; then
    codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
fi
if [ "$codename" != "bookworm" ]; then
    echo "ensure-vulkan: Mesa $version has no ray queries in lavapipe, and no backports suite is known for '${codename:-this system}'; the hardware ray-query path will not run here"
    exit 0
fi
echo "ensure-vulkan: Mesa $version has no ray queries in lavapipe; installing Mesa from bookworm-backports"
need_root "apt-get install -t bookworm-backports mesa-vulkan-drivers"
list=/etc/apt/sources.list.d/aograph-bookworm-backports.list
if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee "$list" >/dev/null
fi
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers >/dev/null
have_vulkan || { echo "ensure-vulkan: the backported lavapipe did not install a Vulkan driver" >&2; exit 1; }
echo "ensure-vulkan: Mesa $(mesa_version) (lavapipe has ray queries)"
