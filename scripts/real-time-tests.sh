#!/usr/bin/env bash
# Prints a ctest -E alternation of the tests bound to the machine's real speed: real-time replays
# (frames paced at the recorded rate, dropped when tracking falls behind) and the tests that
# signal such a replay once it tracks. Under qemu or a sanitizer (10-50x slower) they drop most
# frames, as the live policy says they should, and fail; cross-test.sh and sanitize.sh leave them
# to the native suite (docs/arm.md). One list for both.
set -euo pipefail
tests=(
  'RealtimeReplay\.(OneTimesRealTime|FasterThanRealTime)MatchesOffline'
  'LiveRelocalisation\..*'
  'RunLiveCli\.RealtimeReplayReportsDropsAndLatencyInStatsJson'
  'RunFaults\.(SigtermStopsLikeCtrlCAndKeepsTheResults|AKilledRunLeavesTheTrajectoryOfItsLastFlushWhole)'
)
(IFS='|'; echo "${tests[*]}")
