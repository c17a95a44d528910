#!/usr/bin/env bash
# `cmake --install` gives a prefix that works wherever it is moved: the installed twinray finds its modules and
# the mesh reader it runs in lib/twinray/ beside bin/, never in the build tree (io/shared_module.h). Each load
# and each exec is read from the dynamic loader's own log (LD_DEBUG=files, which the mesh reader inherits).
# The C example of the tracer ABI builds against the moved prefix too.
# Usage: installed_prefix_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"
source_dir="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/installed" >/dev/null
mv "$work/installed" "$work/moved"
twinray="$work/moved/bin/twinray"
cat >"$work/scene.json" <<SCENE
{ "camera": { "eye": [3, 2, 4], "look_at": [0, 0, 0] }, "lights": [{ "position": [5, 5, 5] }],
  "objects": [
    { "type": "mesh", "file": "$source_dir/tests/data/meshes/cube.obj" },
    { "type": "mesh", "file": "$source_dir/tests/data/meshes/cube_binary.stl", "transform": [{ "translate": [0, -2, 0] }] } ] }
SCENE
cd "$work"
export LD_DEBUG=files LD_DEBUG_OUTPUT="$work/loads"
"$twinray" render scene.json --width 32 -o image.png >/dev/null
oiiotool image.png -o image.tif
"$twinray" compare image.tif image.png >/dev/null
embree=0
if [ -e "$work/moved/lib/twinray/libtwinray_embree.so" ]; then
  embree=1
  "$twinray" bench scene.json --runs 1 --width 16 >/dev/null
fi
unset LD_DEBUG LD_DEBUG_OUTPUT
loads="$(cat "$work"/loads.* | grep -E 'twinray_(openimageio|mesh_library|mesh_reader|embree)' |
  grep -E 'dynamically loaded|needed by' | grep -oE '(file=|needed by )[^ ]*twinray_[a-z_]*(\.so)?' | sort -u)"
status=0
for module in libtwinray_openimageio.so libtwinray_mesh_library.so twinray_mesh_reader; do
  if ! grep -q "$work/moved/.*$module" <<<"$loads"; then
    echo "the installed twinray never used $module from the moved prefix"
    status=1
  fi
done
if [ "$embree" -eq 1 ] && ! grep -q "$work/moved/.*libtwinray_embree.so" <<<"$loads"; then
  echo "the installed twinray never used libtwinray_embree.so from the moved prefix"
  status=1
fi
if grep -q "$build" <<<"$loads"; then
  echo "the installed twinray used the build tree:"
  grep "$build" <<<"$loads"
  status=1
fi
# A plug-in builds against the moved prefix alone (find_package(twinray), docs/plugins.md) and exports the entry.
if ! cmake -S "$source_dir/examples" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/moved" >"$work/example.log" 2>&1 ||
  ! cmake --build "$work/example" >>"$work/example.log" 2>&1; then
  echo "the C example did not build against the moved prefix:"
  cat "$work/example.log"
  status=1
elif ! nm -D "$work/example/libbrute_force_tracer.so" | grep -q ' T twinray_tracer_entry$'; then
  echo "the C example built against the moved prefix exports no twinray_tracer_entry"
  status=1
fi
[ "$status" -eq 0 ] && echo "installed prefix, moved: $(wc -l <<<"$loads") loads, all from the prefix"
exit "$status"
