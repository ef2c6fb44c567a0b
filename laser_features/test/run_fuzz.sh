#!/usr/bin/env bash
# Runs the libFuzzer target for a bounded time and writes a JUnit result for catkin.
# Usage: run_fuzz.sh FUZZER SECONDS RESULT_XML
set -u
fuzzer="$1"; seconds="$2"; xml="$3"
corpus="$(mktemp -d)"
mkdir -p "$(dirname "$xml")"
log="$(mktemp)"
start=$(date +%s)
"$fuzzer" -max_total_time="$seconds" -max_len=16384 -print_final_stats=1 "$corpus" > "$log" 2>&1
status=$?
elapsed=$(( $(date +%s) - start ))
runs=$(grep -oE "stat::number_of_executed_units: *[0-9]+" "$log" | grep -oE "[0-9]+$" || echo 0)
tail -n 5 "$log"
if [ "$status" -eq 0 ]; then
  cat > "$xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="fuzz_feature_extractor" tests="1" failures="0" errors="0" time="$elapsed">
  <testcase classname="Fuzz" name="FeatureExtractor_${seconds}s_${runs}_inputs" time="$elapsed"/>
</testsuite>
XML
else
  msg=$(grep -m1 -E "ERROR|violated|SUMMARY" "$log" | sed 's/[<>&"]/_/g')
  cat > "$xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<testsuite name="fuzz_feature_extractor" tests="1" failures="1" errors="0" time="$elapsed">
  <testcase classname="Fuzz" name="FeatureExtractor_${seconds}s" time="$elapsed">
    <failure message="fuzzer exit $status: $msg"/>
  </testcase>
</testsuite>
XML
fi
rm -rf "$corpus" "$log"
exit 0
