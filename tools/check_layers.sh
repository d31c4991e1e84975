#!/usr/bin/env bash
# The layering rule of docs/ARCHITECTURE.md, checked on every build: a file may include only its own layer and the
# layers below it.
#   components (0) -> systems/physics (1) -> engine/core (2) -> systems/{dem,mps,coupling} (3)
#   -> engine/output (4) -> engine/{scene,setup} (5) -> engine/run (6)
# scene and setup share a floor: reading a scene generates its beds and loads its initial grains (setup), and
# loading initial grains reads the scene embedded in their checkpoint (scene).
# Within layer 3 the families stay apart: dem and mps never include each other; coupling may include both.
# Prints every offending include as file:line and exits 1 if there is one.
#   tools/check_layers.sh [source-dir]
set -u
cd "${1:-$(dirname "$0")/..}" || exit 2
rank() {
  case $1 in
    components/*) echo 0 ;;
    systems/physics/*) echo 1 ;;
    engine/core/*) echo 2 ;;
    systems/dem/* | systems/mps/* | systems/coupling/*) echo 3 ;;
    engine/output/*) echo 4 ;;
    engine/scene/* | engine/setup/*) echo 5 ;;
    engine/run/*) echo 6 ;;
    *) echo x ;;
  esac
}
family() { case $1 in systems/dem/*) echo dem ;; systems/mps/*) echo mps ;; *) echo other ;; esac; }
status=0
for file in $(find components systems engine -name '*.hpp' -o -name '*.cpp' | sort); do
  own=$(rank "$file")
  if [ "$own" = x ]; then
    echo "$file: outside every layer (components/, systems/{physics,dem,mps,coupling}/, engine/{core,scene,setup,output,run}/)"
    status=1
    continue
  fi
  while IFS=: read -r line target; do
    other=$(rank "$target")
    if [ "$other" = x ]; then
      echo "$file:$line: includes $target, which is in no layer"
      status=1
    elif [ "$other" -gt "$own" ]; then
      echo "$file:$line: includes $target, a layer above ($other > $own)"
      status=1
    elif [ "$own" = 3 ] && [ "$other" = 3 ]; then
      mine=$(family "$file") theirs=$(family "$target")
      if [ "$mine" != other ] && [ "$theirs" != other ] && [ "$mine" != "$theirs" ]; then
        echo "$file:$line: includes $target: the dem and mps families stay apart (shared code goes to systems/physics)"
        status=1
      fi
    fi
  done < <(grep -n '^#include "' "$file" | sed -E 's/^([0-9]+):#include "([^"]+)".*/\1:\2/')
done
[ $status -eq 0 ] || echo "layering violated (docs/ARCHITECTURE.md, 'Layers')"
exit $status
