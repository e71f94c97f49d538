#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and checks what an engine team gets:
#  1. the licence and third-party notices, the joint maps and profiles, a pkg-config file
#     naming the licence;
#  2. a C program built against the C API alone, with CMake (find_package(marionette
#     COMPONENTS c)) while every private dependency's package is disabled, and with
#     pkg-config;
#  3. libmarionette_c exports only mn_ symbols, links no GPL code (espeak-ng) nor what it drags in (X11, PulseAudio,
#     ALSA), and the exported targets hold no absolute path to a library of this machine;
#  4. a C++ consumer with find_package(marionette), finding only GLM and Threads.
set -euo pipefail
build=$1
consumer=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "package: FAILED: $*" >&2; exit 1; }
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null

# 1. What travels with the package.
[ -f "$prefix/share/doc/marionette/LICENSE" ] || fail "the licence is not installed (share/doc/marionette/LICENSE)"
grep -q "MIT License" "$prefix/share/doc/marionette/LICENSE" || fail "the installed LICENSE is not the MIT licence"
grep -q "espeak-ng" "$prefix/share/doc/marionette/THIRD_PARTY_NOTICES.md" || fail "the third-party notices are not installed"
[ -f "$prefix/share/marionette/jointmaps/RobotExpressive.json" ] || fail "the joint maps are not installed"
[ -f "$prefix/share/marionette/profiles/RobotExpressive.json" ] || fail "the profiles are not installed"
config=$(find "$prefix" -name marionetteConfig.cmake)
grep -q 'marionette_LICENSE "MIT"' "$config" || fail "the CMake package does not name its licence"

# 2. and 3. The C API alone.
libc=$(find "$prefix" -name 'libmarionette_c.so' | head -1)
[ -n "$libc" ] && [ -f "$libc" ] || fail "libmarionette_c.so is not installed"
needed=$(readelf -d "$libc" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p')
for gpl in espeak pulse asound X11 sonic pcaudio; do
  if echo "$needed" | grep -qi "$gpl"; then fail "libmarionette_c.so needs $(echo "$needed" | grep -i "$gpl" | tr '\n' ' ')"; fi
done
# Only the C API's own functions are exported (bridge/c_api/marionette_c.map).
for lib in "$libc" $(find "$prefix" -name 'libmarionette_c_espeak.so' | head -1); do
  others=$(nm -D --defined-only "$lib" | awk '{print $NF}' | grep -v '^mn_' || true)
  [ -z "$others" ] || fail "$(basename "$lib") exports symbols other than mn_: $(echo "$others" | head -5 | tr '\n' ' ')"
  count=$(nm -D --defined-only "$lib" | grep -c ' mn_' || true)
  [ "$count" -ge 50 ] || fail "$(basename "$lib") exports only $count mn_ functions"
done
if grep -l "/usr/lib" "$(dirname "$config")"/marionette*Targets*.cmake; then
  fail "an exported target names a library by its absolute path on the build machine"
fi
disabled=()
for p in assimp OpenImageIO embree pugixml TinyGLTF nlohmann_json glm Imath; do
  disabled+=("-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON")
done
cmake --no-warn-unused-cli -S "$here/c_only" -B "$work/c_only" -DCMAKE_PREFIX_PATH="$prefix" "${disabled[@]}" >"$work/c_only.log" 2>&1 ||
  { cat "$work/c_only.log"; fail "find_package(marionette COMPONENTS c) needs more than the C API"; }
if grep -qi "warning" "$work/c_only.log"; then cat "$work/c_only.log"; fail "configuring a C consumer prints warnings"; fi
cmake --build "$work/c_only" >/dev/null
"$work/c_only/c_only"
pc=$(dirname "$(find "$prefix" -name marionette_c.pc)")
[ -d "$pc" ] || fail "marionette_c.pc is not installed"
grep -q "MIT" "$pc/marionette_c.pc" || fail "marionette_c.pc does not name the licence"
flags=$(PKG_CONFIG_PATH="$pc" pkg-config --cflags --libs marionette_c)
libdir=$(PKG_CONFIG_PATH="$pc" pkg-config --variable=libdir marionette_c)
cc -std=c11 "$here/c_only/c_only.c" -o "$work/c_pkgconfig" $flags -Wl,-rpath,"$libdir"
"$work/c_pkgconfig"

# 4. The C++ libraries: the headers need GLM; the private dependencies are linked by name.
cxx_disabled=()
for p in assimp OpenImageIO embree pugixml TinyGLTF nlohmann_json Imath; do
  cxx_disabled+=("-DCMAKE_DISABLE_FIND_PACKAGE_$p=ON")
done
cmake -S "$consumer" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release "${cxx_disabled[@]}" >/dev/null
cmake --build "$work/build" >/dev/null
"$work/build/consumer"
