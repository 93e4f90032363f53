#!/usr/bin/env bash
# Installs every Debian 12 package rostro builds and runs with. Idempotent: packages
# already present are left alone, so running it twice is cheap.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang-format git
  libeigen3-dev libopencv-dev libceres-dev libapriltag-dev
  libv4l-dev v4l-utils libcamera-dev
  libespeak-ng-dev espeak-ng-data
  libegl-dev libgl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  liblo-dev ffmpeg
  libdlib-dev libdlib-data
  libavformat-dev libavcodec-dev libswresample-dev libavutil-dev
  libpocketsphinx-dev libsphinxbase-dev pocketsphinx-en-us
  flite alsa-utils
  liblua5.4-dev
  # sound for `rostro play --window` (SDL2 audio); `rostro edit`'s interface (Dear ImGui)
  libsdl2-dev libimgui-dev
  # the window tests (tests/apps/window_test.cpp): an X server without a screen, keys,
  # screenshots
  xvfb xdotool x11-apps imagemagick
  # the shoot workflow (workflow/, `rostro shoot`) and its report's plot
  snakemake python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
