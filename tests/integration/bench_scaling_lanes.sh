#!/usr/bin/env bash
# tests/integration/bench_scaling_lanes.sh — tests/bench/bench_scaling --schedule lanes (issue 36:
# the whole-lane schedule modelled from the isolated-lane engine): a short run at two K on the 1%
# bunny writes --json with, per K, the measured lane costs and, per modelled worker count, the
# speed-up and the efficiency (and the coordinator's CPU per evaluation); the human report names
# the same (per K also the prediction without the group barrier and the modelled evaluations per
# second); a K outside 2..1024 or an unknown schedule is refused with one line. The runs take the
# job's own set-up (its start, attributes, views, tuning, regrids: co_job_setup_make) and, with
# --coordinator-workers, measure the coordinator's CPU on a --lanes remote run of local workers;
# --initial takes a saved start; the image start and --initial with --target-verts are refused.
# No timing asserts.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.bash"
: "${LUMESH_TEST_DATA:?}" "${LUMESH_BUILD:?}"
bench="$LUMESH_BUILD/tests/bench/bench_scaling"
[ -x "$bench" ] || { echo "bench_scaling_lanes.sh: $bench is not built"; exit 1; }
scratch
model="$LUMESH_TEST_DATA/cache/meshes/bunny00.off"
[ -f "$model" ] || { echo "bench_scaling_lanes.sh: no $model"; exit 77; }
export LP_NUM_THREADS=0

# -- bad arguments: one line, exit 1 --
expect_fail_line "$bench" "$model" --schedule lanes --lanes-k 1
expect_fail_line "$bench" "$model" --schedule lanes --lanes-k 2,1025
expect_fail_line "$bench" "$model" --schedule lanes --lanes-per-worker 0
expect_fail_line "$bench" "$model" --schedule lane
expect_fail_line "$bench" "$model" --schedule lanes --start image
expect_fail_line "$bench" "$model" --schedule lanes --initial "$model" --target-verts 300

# -- a short run at K 2 and 4: the JSON's keys --
checks=$((checks + 1))
if ! "$bench" "$model" --schedule lanes --lanes-k 2,4 --edge-evals 1200 --views 8 --size 96 \
  --regrid-every 300 --coordinator-workers 1 --json \
  >"$tmp/lanes.json" 2>"$tmp/lanes.err"; then
  fail "bench_scaling --schedule lanes --json failed: $(tail -3 "$tmp/lanes.err")"
fi
checks=$((checks + 1))
python3 - "$tmp/lanes.json" <<'PY' || fail "bench_scaling --schedule lanes: its JSON lacks keys"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["bench"] == "scaling" and j["schedule"] == "lanes", j
assert j["start"] == "qem" and j["start_verts"] >= 100 and j["views"] == 8 and j["size"] == 96, j
assert [r["edges_in_flight"] for r in j["lanes"]] == [2, 4], j["lanes"]
want_w = [1, 2, 4, 8, 16, 128]
for r in j["lanes"]:
    for k in ("groups", "lanes", "evals", "evals_per_lane_mean", "evals_per_lane_p90",
              "evals_per_lane_max", "worker_us_per_eval", "coordinator_merge_us_per_lane",
              "coordinator_cpu_per_eval_us", "dropped_replay_share",
              "dropped_revalidation_share", "revalidated_kept_share", "wasted_evals_share",
              "request_bytes", "result_bytes_mean", "commit_bytes_per_group", "energy_rel",
              "regrids", "regrid_cpu_s", "regrid_target_cpu_s", "target_bytes"):
        assert k in r, (k, r)
    c = r["coordinator_measured"]
    for k in ("workers", "groups", "evals", "plan_ms_per_group", "dispatch_ms_per_group",
              "merge_ms_per_group", "cpu_per_eval_us", "cpu_per_eval_us_with_regrids", "audits",
              "regrids", "evals_per_s"):
        assert k in c, (k, c)
    assert c["workers"] == 1 and c["evals"] >= 1 and c["cpu_per_eval_us"] > 0, c
    assert c["groups"] == r["groups"] and c["evals"] == r["evals"], (c, r)  # the job's groups
    assert r["regrids"] == 0 or r["regrid_cpu_s"] > 0, r
    # the targets' renders are part of a regrid; one targets asset: 8 views of 96x96 and a header
    assert r["regrids"] == 0 or 0 < r["regrid_target_cpu_s"] <= r["regrid_cpu_s"] + 1e-4, r
    assert r["regrids"] == 0 or r["target_bytes"] == 20 + 8 * 96 * 96, r
    assert r["lanes"] >= 1 and r["evals"] >= 1 and r["evals_per_lane_max"] >= 1, r
    assert [p["workers"] for p in r["predicted"]] == want_w, r["predicted"]
    for p in r["predicted"]:
        assert p["speedup_no_barrier"] >= p["speedup"] - 1e-3 and p["evals_per_s"] > 0, p
        assert p["coordinator_cpu_per_eval_us"] > 0, p
assert any(r["regrids"] >= 1 for r in j["lanes"]), j["lanes"]
assert [p["workers"] for p in j["predicted"]] == want_w, j["predicted"]
for p in j["predicted"]:
    for k in ("speedup", "efficiency", "edges_in_flight", "coordinator_cpu_per_eval_us",
              "speedup_no_barrier"):
        assert k in p, (k, p)
    assert p["speedup"] > 0 and abs(p["efficiency"] - p["speedup"] / p["workers"]) < 1e-2, p
# one worker: at most 1 (the measured coordinator CPU of the remote run comes on top)
assert 0.5 < j["predicted"][0]["speedup"] <= 1 + 1e-2, j["predicted"][0]
PY

# -- the human report: per K a line, the predictions, where the time goes --
checks=$((checks + 1))
"$LUMESH_BUILD/coordinator/lumesh" simplify "$model" -o "$tmp/start.obj" --target-verts 200 \
  >"$tmp/simplify.txt" 2>&1 || fail "lumesh simplify failed: $(tail -3 "$tmp/simplify.txt")"
"$bench" "$model" --schedule lanes --initial "$tmp/start.obj" --lanes-k 2 --edge-evals 600 \
  --views 8 --size 96 --coordinator-workers 1 >"$tmp/lanes.txt" 2>&1 ||
  fail "bench_scaling --schedule lanes failed: $(tail -3 "$tmp/lanes.txt")"
for want in "K 2:" "evaluations per lane mean" "per evaluation" "predicted at 100 us RTT" \
  "where the time goes" "without the group barrier" "evaluations per second" \
  "start.obj (" "the coordinator measured on --lanes remote" \
  "measured on a remote run"; do
  checks=$((checks + 1))
  grep -q "$want" "$tmp/lanes.txt" || fail "the human report lacks '$want'"
done

finish
