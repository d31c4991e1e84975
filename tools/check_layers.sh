#!/usr/bin/env bash
# The floors of docs/ARCHITECTURE.md, checked on every build: a file may include only its own floor and the
# floors below it.
#   components (0: the data and the World that holds them)
#   -> systems/physics and the System contract systems/system.hpp (1: laws, numerics, measures; no system)
#   -> systems/{dem,mps,coupling} (2: the systems) -> engine/{core,output,toml} (3: scheduler, output, TOML reading)
#   -> engine/setup (4: beds, layout, initial state, the budget) -> engine/scene (5: the scene read into the model)
#   -> engine/run (6: registry, stepper, run loop, CLI)
# Within floors 1 and 2 the families stay apart: dem, mps and mean_flow (systems/<family> and
# systems/physics/<family>) never include one another; coupling may include all of them.
# Prints every offending include as file:line and exits 1 if there is one.
#   tools/check_layers.sh [source-dir]
set -u
cd "${1:-$(dirname "$0")/..}" || exit 2
rank() {
  case $1 in
    components/*) echo 0 ;;
    systems/physics/* | systems/system.hpp | systems/system.cpp) echo 1 ;;
    systems/dem/* | systems/mps/* | systems/mean_flow/* | systems/coupling/*) echo 2 ;;
    engine/core/* | engine/output/* | engine/toml/*) echo 3 ;;
    engine/setup/*) echo 4 ;;
    engine/scene/*) echo 5 ;;
    engine/run/*) echo 6 ;;
    *) echo x ;;
  esac
}
family() {
  case $1 in
    systems/dem/* | systems/physics/dem/*) echo dem ;;
    systems/mps/* | systems/physics/mps/*) echo mps ;;
    systems/mean_flow/* | systems/physics/mean_flow/*) echo mean_flow ;;
    *) echo other ;;
  esac
}
status=0
for file in $(find components systems engine -name '*.hpp' -o -name '*.cpp' | sort); do
  own=$(rank "$file")
  if [ "$own" = x ]; then
    echo "$file: outside every floor (components/, systems/{physics,dem,mps,mean_flow,coupling}/, engine/{core,output,toml,setup,scene,run}/)"
    status=1
    continue
  fi
  while IFS=: read -r line target; do
    other=$(rank "$target")
    if [ "$other" = x ]; then
      echo "$file:$line: includes $target, which is on no floor"
      status=1
    elif [ "$other" -gt "$own" ]; then
      echo "$file:$line: includes $target, a floor above ($other > $own)"
      status=1
    elif [ "$own" -le 2 ] && [ "$other" -le 2 ]; then
      mine=$(family "$file") theirs=$(family "$target")
      if [ "$mine" != other ] && [ "$theirs" != other ] && [ "$mine" != "$theirs" ]; then
        echo "$file:$line: includes $target: the dem, mps and mean_flow families stay apart (shared code goes to systems/physics)"
        status=1
      fi
    fi
  done < <(grep -n '^#include "' "$file" | sed -E 's/^([0-9]+):#include "([^"]+)".*/\1:\2/')
done
[ $status -eq 0 ] || echo "floors violated (docs/ARCHITECTURE.md, 'Floors')"
exit $status
