# The H200 measurement behind h200-observation-on-gpu.json: run on the
# device machine from the project root with the bundle of README.md here in
# .devbundle/bundle.tgz (carry .devbundle), e.g. cp reports/benchmarks/h200-observation.sh .devbundle/run.sh
set -e
mkdir -p /tmp/b && tar -C /tmp/b -xzf .devbundle/bundle.tgz
export VK_ICD_FILENAMES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json LD_LIBRARY_PATH=/tmp/b/lib
G=/tmp/b/bin/giharness
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
run() { # name scenario extra-args
  local n=$1 s=$2; shift 2
  /usr/bin/time -f "$n wall %e s" $G run scenarios/bench/$s.json --backend bvh --out /tmp/r_$n "$@" > $OUT/$n.log 2>&1 || echo "$n exit $?"
  tail -1 $OUT/$n.log
  cp /tmp/r_$n/summary.json $OUT/$n.summary.json || true
  python3 - /tmp/r_$n/summary.json $n <<'PY'
import json,sys
s=json.load(open(sys.argv[1])); t=s['timings']
print(sys.argv[2], json.dumps(t.get('frame')), 'verdict', s.get('verdict'), 'wall_s', round(s['wall_seconds'],2))
print('  ', {k: round(v['median_ms'],3) for k,v in t['passes'].items()})
print('  timestamp_period_ns', s['device'].get('timestamp_period_ns'))
PY
}
run warmup full_cornell_1600x900 > /dev/null
run cornell_hashlog full_cornell_1600x900 --hash-log
run cornell full_cornell_1600x900
run glossy_hashlog full_glossy_room_1600x900 --hash-log
run glossy full_glossy_room_1600x900
run hd1000_hashlog full_cornell_1920x1080_1000 --hash-log
run hd1000 full_cornell_1920x1080_1000
run cornell_hashlog2 full_cornell_1600x900 --hash-log
# The 1042-spawn cliff, drawn (at most 7 minutes).
/usr/bin/time -f "cliffs wall %e s" timeout 420 $G run scenarios/bench/cluster_ids_1042_cliffs_rendered.json --backend bvh --out /tmp/r_cliffs > $OUT/cliffs.log 2>&1 || echo "cliffs exit $?"
tail -2 $OUT/cliffs.log
cp /tmp/r_cliffs/summary.json $OUT/cliffs.summary.json 2>/dev/null || true
python3 -c "
import json;s=json.load(open('/tmp/r_cliffs/summary.json'));c=s['checks'][0];print(c['verdict'], json.dumps(c['figures'].get('overflow')), json.dumps(c['figures'].get('rendered_overflow')), s['wall_seconds'])" || true
