#!/usr/bin/env bash
# The client SDK as a downstream user gets it (ctest runs this as sdk_downstream):
#   1. cmake --install the build tree into a fresh prefix;
#   2. build the example of docs/client-sdk.md with find_package(omnisweep), and again with
#      pkg-config alone;
#   3. run both against an omnisweep-server serving a small synthetic dataset on loopback: each
#      receives a frame and renders a novel view.
# usage: run_downstream.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
src=$1
build=$2
work=$build/tests/downstream
rm -rf "$work"
mkdir -p "$work/project"

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
awk '/<!-- example:begin -->/{on=1; next} /<!-- example:end -->/{on=0} on' "$src/docs/client-sdk.md" |
  sed '/^```/d' > "$work/project/example.cc"
[[ -s $work/project/example.cc ]] || { echo "no example found in docs/client-sdk.md" >&2; exit 1; }
cp "$src/tests/downstream/CMakeLists.txt" "$work/project/"

cmake -S "$work/project" -B "$work/cmake-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/cmake-build" > "$work/build.log"
echo "built with find_package(omnisweep): $work/cmake-build/example"
PKG_CONFIG_PATH=$work/prefix/lib/pkgconfig
export PKG_CONFIG_PATH
# The headers an app includes (the subscriber, the reprojector, the context) need the Vulkan C
# headers only: Vulkan-Hpp and its NDEBUG rule stay inside the SDK.
# shellcheck disable=SC2046
if c++ -std=c++20 -E -dM "$work/project/example.cc" $(pkg-config --cflags omnisweep) |
  grep -q '^#define VULKAN_HPP '; then
  echo "the example's omnisweep headers pull in Vulkan-Hpp (vulkan.hpp)" >&2
  exit 1
fi
# As a Debug build of an app that uses Vulkan-Hpp itself compiles it: without NDEBUG, with
# <vulkan/vulkan.hpp> included before any omnisweep header.
# shellcheck disable=SC2046
c++ -O1 -g -include vulkan/vulkan.hpp "$work/project/example.cc" -o "$work/example-pkgconfig" \
  $(pkg-config --cflags --libs omnisweep)
echo "built with pkg-config omnisweep, Vulkan-Hpp first and no NDEBUG: $work/example-pkgconfig"

"$build/bin/omnisweep-synth" -o "$work/data" -n 2 --image-size 160 --panorama 64 32 > /dev/null 2>&1
domain=$((201 + $$ % 30))
prefix=downstream$$
"$build/bin/omnisweep-server" --source "dataset:$work/data" --matching-resolution 128 128 \
  --panorama-resolution 256 128 --candidates 16 --fps 5 --log-interval 0 \
  --domain "$domain" --topic-prefix "$prefix" > "$work/server.log" 2>&1 &
server=$!
trap 'kill -TERM $server 2>/dev/null || true; wait $server 2>/dev/null || true' EXIT
for example in "$work/cmake-build/example" "$work/example-pkgconfig"; do
  (cd "$work" && "$example" "$domain" "$prefix" 60)
done
