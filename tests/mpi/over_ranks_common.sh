# What the command-line tests over MPI ranks share (sourced after RIFFLE, MPIEXEC, SRC and WORK are set): a fresh
# work folder, Open MPI's settings, `check` and `ranks`. RANKS_TIMEOUT: the seconds one riffle run may take (120).
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 2
# Root allowed (CI runs as root), more ranks than cores allowed, and ranks that yield while they wait for another.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_mpi_yield_when_idle=1
failures=0
check() {  # check DESCRIPTION COMMAND...
  local description=$1
  shift
  if "$@"; then echo "ok: $description"; else echo "FAILED: $description"; failures=$((failures + 1)); fi
}
ranks() {  # ranks N ARGS...: riffle on N ranks (1: without mpiexec)
  local n=$1 limit=${RANKS_TIMEOUT:-120}
  shift
  if [ "$n" = 1 ]; then timeout -k 5 "$limit" "$RIFFLE" "$@"; else timeout -k 5 "$limit" "$MPIEXEC" -n "$n" "$RIFFLE" "$@"; fi
}
