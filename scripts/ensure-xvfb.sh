#!/usr/bin/env bash
# Makes sure the viewer's tests can open a window: when `xvfb-run` is missing, installs Xvfb
# (Debian/Ubuntu package xvfb) and the X11 client libraries winit loads at run time (Xcursor,
# Xrandr, XInput2, xkbcommon-x11). Needs root or sudo only when it has to install.
set -euo pipefail

have_all() {
    command -v xvfb-run >/dev/null 2>&1 || return 1
    local libs
    libs=$(ldconfig -p 2>/dev/null || true)
    local lib
    for lib in libX11.so.6 libXcursor.so.1 libXrandr.so.2 libXi.so.6 libxkbcommon-x11.so.0; do
        case "$libs" in *"$lib"*) ;; *) return 1 ;; esac
    done
}

if have_all; then
    echo "ensure-xvfb: xvfb-run and the X11 libraries are installed"
    exit 0
fi

echo "ensure-xvfb: installing Xvfb and X11 client libraries (xvfb, libxcursor1, libxrandr2, libxi6, libxkbcommon-x11-0)"
SUDO=""
if [ "$(id -u)" != "0" ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
        echo "ensure-xvfb: not root and no sudo; run as root: apt-get install xvfb libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0" >&2
        exit 1
    fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq xvfb xauth libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 >/dev/null
have_all || { echo "ensure-xvfb: the install did not provide xvfb-run and the X11 libraries" >&2; exit 1; }
echo "ensure-xvfb: installed"
