# shellcheck shell=bash
# The sanitizer run of scripts/test (sourced after scripts/lib/setup.sh, not run).
#
# Builds the library and the gtests (not the rostests) with AddressSanitizer, LeakSanitizer and
# UndefinedBehaviorSanitizer (CMake option AMCR_SANITIZE) in a workspace of their own, runs every
# gtest binary with its results in XML, and counts as a failure every binary that ends non-zero
# and every sanitizer report, also those of the programs the tests start (amcr_offline).
#
# Functions: amcr_gtest_targets, amcr_sanitizer_environment, amcr_run_sanitized_gtests.

# The catkin_add_gtest targets of CMakeLists.txt (the rostests need a master: not run here).
amcr_gtest_targets() {
  sed -n 's/^[[:space:]]*catkin_add_gtest(\([A-Za-z0-9_]*\).*/\1/p' "$AMCR_REPO/CMakeLists.txt"
}

# Sanitizer options for every process started from here on. ASan and LSan reports go to files
# under $1 (one per process, named by its pid), so that a report of a child process is not lost in
# the output that a test checks, and is found after the run. (GCC's UBSan runtime prints to
# stderr all the same; it stops the process, whose exit code the test or this script sees.)
amcr_sanitizer_environment() {
  local reports="$1"
  mkdir -p "$reports"
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=0:log_path=$reports/asan"
  export LSAN_OPTIONS="suppressions=$AMCR_REPO/scripts/lib/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/ubsan"
}

# Gtest binaries whose processes may reach the libgphoto2_port leak of scripts/lib/lsan.supp
# (test_amcr_offline starts amcr_offline on files that are no image): that suppression matches on
# the full stack of the allocation only, so these run with fast_unwind_on_malloc=0 (about twice
# as slow; the others keep the fast unwinder).
AMCR_FULL_STACK_GTESTS=(test_amcr_offline)

# Runs each gtest binary (names in "$@") from devel/lib/amcr with XML output into $1, then
# records a failure for each binary that failed without saying why in its XML (a sanitizer
# stopped it, or it crashed) and one for each sanitizer report. Returns 1 when anything failed.
amcr_run_sanitized_gtests() {
  local results="$1"
  shift
  local reports="$results/sanitizer_reports" bin_dir="$AMCR_WS/devel/lib/amcr" name rc failed=0 report
  amcr_sanitizer_environment "$reports"
  for name in "$@"; do
    [[ -x "$bin_dir/$name" ]] || amcr_die "gtest binary $bin_dir/$name was not built"
    echo "---- $name"
    rc=0
    local asan_options="$ASAN_OPTIONS"
    [[ " ${AMCR_FULL_STACK_GTESTS[*]} " != *" $name "* ]] || asan_options+=":fast_unwind_on_malloc=0"
    (cd "$AMCR_REPO" && ASAN_OPTIONS="$asan_options" timeout --kill-after=10 "${AMCR_SANITIZE_TIMEOUT:-1800}" \
      "$bin_dir/$name" --gtest_output="xml:$results/$name.xml") || rc=$?
    if ((rc != 0)); then
      failed=1
      /usr/bin/python3 "$AMCR_REPO/scripts/lib/test_summary.py" --record-failure "$results" "$name" \
        "$name exited with code $rc (sanitizer report, crash or failed test)"
    fi
  done
  shopt -s nullglob
  for report in "$reports"/*; do
    failed=1
    echo "---- sanitizer report $report"
    cat "$report"
    /usr/bin/python3 "$AMCR_REPO/scripts/lib/test_summary.py" --record-failure "$results" \
      "sanitizer_report.$(basename "$report")" "$(grep -m1 -E 'ERROR|runtime error' "$report" || head -n1 "$report")"
  done
  shopt -u nullglob
  return "$failed"
}
