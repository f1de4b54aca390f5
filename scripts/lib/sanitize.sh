# shellcheck shell=bash
# The sanitizer run of scripts/test (sourced after scripts/lib/setup.sh, not run).
#
# Builds the library and the gtests (not the rostests) with clang's AddressSanitizer, LeakSanitizer
# and UndefinedBehaviorSanitizer (CMake option AMCR_SANITIZE) in a workspace of their own, runs every
# gtest binary with its results in XML, and counts as a failure every binary that ends non-zero
# and every sanitizer report, also those of the programs the tests start (amcr_offline).
#
# Functions: amcr_sanitizer_compiler, amcr_gtest_targets, amcr_sanitizer_environment,
# amcr_run_sanitized_gtest (one binary), amcr_run_sanitized_gtests (all of them, side by side).

# How the sanitizer workspace is configured: clang, which builds it two to three times as fast as
# GCC with the same sanitizers, RelWithDebInfo for the reports' file and line.
AMCR_SANITIZE_CMAKE_ARGS=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DAMCR_SANITIZE=ON
  -DCMAKE_BUILD_TYPE=RelWithDebInfo)

# A sanitizer workspace configured with another compiler (GCC, before the build was clang's) is
# configured anew: CMake keeps the compiler of a build tree's first configuration.
amcr_sanitizer_compiler() {
  local cache="$AMCR_WS/build/CMakeCache.txt"
  if [[ -f "$cache" ]] && ! grep -qE '^CMAKE_CXX_COMPILER:[A-Z]+=(.*/)?clang\+\+$' "$cache"; then
    echo "build/ was configured with another compiler: removing build/ and devel/"
    rm -rf "$AMCR_WS/build" "$AMCR_WS/devel"
  fi
}

# The catkin_add_gtest targets of CMakeLists.txt (the rostests need a master: not run here).
amcr_gtest_targets() {
  sed -n 's/^[[:space:]]*catkin_add_gtest(\([A-Za-z0-9_]*\).*/\1/p' "$AMCR_REPO/CMakeLists.txt"
}

# Sanitizer options for every process started from here on. ASan and LSan reports go to files
# under $1 (one per process, named by its pid), so that a report of a child process is not lost in
# the output that a test checks, and is found after the run; UBSan's too. UBSan stops the process
# at its first report, whose exit code the test or this script sees as well.
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

# The gtest binaries that take longest under the sanitizers, in that order: they start first, so
# that the binaries run side by side finish at about the same time. Any binary not named here
# starts after them, in the order of CMakeLists.txt.
# (Measured on 2 cores, two at a time: 560, 360, 170, 120 and 70 s.)
AMCR_LONGEST_GTESTS=(test_amcr_recognition test_amcr_tracking test_amcr_core test_amcr_baselines test_amcr_offline)

# A binary's time limit under the sanitizers, s (AMCR_SANITIZE_TIMEOUT); past 60 % of it the run
# warns, so that a binary grows shorter before it fails for time.
AMCR_SANITIZE_LIMIT="${AMCR_SANITIZE_TIMEOUT:-1800}"

# Runs one gtest binary ($2) with XML output into $1; its output goes to $1/logs/$2.log, its exit
# code and seconds to $1/logs/$2.rc.
amcr_run_sanitized_gtest() {
  local results="$1" name="$2" bin_dir="$AMCR_WS/devel/lib/amcr" rc=0 started=$SECONDS
  local asan_options="$ASAN_OPTIONS"
  [[ " ${AMCR_FULL_STACK_GTESTS[*]} " != *" $name "* ]] || asan_options+=":fast_unwind_on_malloc=0"
  (cd "$AMCR_REPO" && ASAN_OPTIONS="$asan_options" timeout --kill-after=10 "$AMCR_SANITIZE_LIMIT" \
    "$bin_dir/$name" --gtest_output="xml:$results/$name.xml") >"$results/logs/$name.log" 2>&1 || rc=$?
  echo "$rc $((SECONDS - started))" >"$results/logs/$name.rc"
}

# Runs each gtest binary (names in "$@") from devel/lib/amcr with XML output into $1, $AMCR_JOBS at
# a time (the longest first), and prints each one's output and time as it ends; then records a
# failure for each binary that failed without saying why in its XML (a sanitizer stopped it, or it
# crashed) and one for each sanitizer report. Returns 1 when anything failed.
amcr_run_sanitized_gtests() {
  local results="$1"
  shift
  local reports="$results/sanitizer_reports" bin_dir="$AMCR_WS/devel/lib/amcr" name failed=0 report
  local ordered=() pending=() rc seconds
  amcr_sanitizer_environment "$reports"
  mkdir -p "$results/logs"
  for name in "${AMCR_LONGEST_GTESTS[@]}"; do
    [[ " $* " != *" $name "* ]] || ordered+=("$name")
  done
  for name in "$@"; do
    [[ -x "$bin_dir/$name" ]] || amcr_die "gtest binary $bin_dir/$name was not built"
    [[ " ${ordered[*]} " == *" $name "* ]] || ordered+=("$name")
  done
  # Prints the output of each binary that has ended, once, with its time.
  report_ended() {
    local left=() n
    for n in "${pending[@]}"; do
      if [[ ! -f "$results/logs/$n.rc" ]]; then
        left+=("$n")
        continue
      fi
      read -r rc seconds <"$results/logs/$n.rc"
      echo "---- $n (exit code $rc, ${seconds} s of its ${AMCR_SANITIZE_LIMIT} s)"
      cat "$results/logs/$n.log"
      if ((seconds * 10 > AMCR_SANITIZE_LIMIT * 6)); then
        echo "warning: $n took ${seconds} s under the sanitizers, over 60 % of its ${AMCR_SANITIZE_LIMIT} s limit" \
          "(AMCR_SANITIZE_TIMEOUT): shorten its runs (test/run_length.h)"
      fi
      if ((rc != 0)); then
        failed=1
        /usr/bin/python3 "$AMCR_REPO/scripts/lib/test_summary.py" --record-failure "$results" "$n" \
          "$n exited with code $rc (sanitizer report, crash, failed test or over its time limit)"
      fi
    done
    pending=("${left[@]}")
  }
  echo "running ${#ordered[@]} gtest binaries, $AMCR_JOBS at a time: ${ordered[*]}"
  for name in "${ordered[@]}"; do
    while (($(jobs -rp | wc -l) >= AMCR_JOBS)); do
      wait -n || true
      report_ended
    done
    rm -f "$results/logs/$name.rc"
    amcr_run_sanitized_gtest "$results" "$name" &
    pending+=("$name")
  done
  wait
  report_ended
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
