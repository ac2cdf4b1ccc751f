#!/usr/bin/env bash
# Checks that every stage includes only the stages docs/ARCHITECTURE.md allows it; prints each
# offending line (file:line: include) and exits 1, or exits 0 when the layering holds.
set -euo pipefail
cd "$(dirname "$0")/.."

# stage -> the stages it may include (itself always). Keep in step with docs/ARCHITECTURE.md.
declare -A allowed=(
  [core]=""
  [io]="core"
  [volume]="core io"
  [model]="core io"
  [gpu]="core io volume"
  [sim]="core io volume model"
  [devices]="core io"
  [eval]="core io volume model sim"
  [render]="core io volume model gpu"
  [audio]="core io volume model sim"
  [ui]="core io volume model gpu sim eval render audio devices"
  [bench]="core io volume model gpu sim eval"
  [app]="core io volume model gpu sim eval render audio ui devices bench"
)

folder() { case "$1" in devices|bench) echo "$1" ;; *) echo "src/$1" ;; esac; }

status=0
for stage in "${!allowed[@]}"; do
  dir=$(folder "$stage")
  [ -d "$dir" ] || continue
  ok=" $stage ${allowed[$stage]} "
  while IFS= read -r hit; do
    included=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"$hit")
    # Only the project's stages are checked; generated headers ("compute/...", "shaders/...") and
    # the layout headers they share are not stages.
    [ -n "${allowed[$included]+x}" ] || continue
    if [[ "$ok" != *" $included "* ]]; then
      echo "$hit: $stage may not include $included"
      status=1
    fi
  done < <(grep -rnE '^#include "[a-z_]+/' "$dir" --include='*.h' --include='*.cpp' || true)
done
exit $status
