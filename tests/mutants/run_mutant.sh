#!/usr/bin/env bash
# Runs one mutant's conformance suite (tests/mutants/CMakeLists.txt). The ctest test passes when the suite
# fails, that is when the mutant is caught, and prints one row of the mutation table: the mutant, how many
# tests failed and which. A mutant every test passes has survived: the suite could not see its bug.
set -uo pipefail
binary="$1"
mutant="$2"
output="$("$binary" --gtest_brief=1 2>&1)"
status=$?
failed="$(sed -n 's/^\[  FAILED  \] \([A-Za-z][^ ,]*\).*/\1/p' <<<"$output" | sort -u)"
count=$(grep -c . <<<"$failed")
if [ "$status" -eq 0 ]; then
  echo "mutant | $mutant | SURVIVED | every conformance test passed"
  exit 1
fi
if [ -z "$failed" ]; then
  echo "mutant | $mutant | caught | the suite stopped with status $status before any test failed:"
  tail -5 <<<"$output"
  exit 0
fi
# The attribution's verdict (accuracy/attribution.h): how many of the scenes' differing pixels no float
# rounding explains, summed over the "[ measured ] scene ... unexplained N" lines.
unexplained="$(awk '/^\[ measured \]/ && / drift / { for (i = 1; i < NF; i++) if ($i == "unexplained") sum += $(i + 1) }
                    END { print sum + 0 }' <<<"$output")"
echo "mutant | $mutant | caught by $count, $unexplained unexplained pixels | $(head -3 <<<"$failed" | tr '\n' ' ')"
# The first failure's message: what the suite saw.
grep -m 1 -A 3 'Failure$' <<<"$output"
exit 0
