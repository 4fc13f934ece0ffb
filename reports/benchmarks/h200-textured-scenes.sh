# The H200 record behind h200-textured-scenes.json: the textured
# scenes of the default suite at their nightly settings (verdicts and GPU
# ms), then the atrium and the 1 M-triangle atrium at 1280x720 (per-pass GPU
# medians), with --backend bvh (the driver has no ray queries). The 1 M glb
# is generated there by its script, as .ci/build does here. Run on the device
# machine from the project root with the bundle of README.md in
# .devbundle/bundle.tgz (carry .devbundle):
#   cp reports/benchmarks/h200-textured-scenes.sh .devbundle/run.sh; bash .devbundle/run.sh
set -e
mkdir -p /tmp/b && tar -C /tmp/b -xzf .devbundle/bundle.tgz
export VK_ICD_FILENAMES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json LD_LIBRARY_PATH=/tmp/b/lib
G=/tmp/b/bin/giharness
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $OUT/runs.log
/usr/bin/time -f "generate atrium_1m wall %e s" python3 scenarios/assets/make_atrium.py --triangles 1000000 \
    --materials 64 --glb --name atrium_1m --out scenarios/assets/generated >> $OUT/runs.log 2>&1
summaries=()
for s in textured_room textured_room_di textured_room_gi atrium atrium_1m; do
  /usr/bin/time -f "$s wall %e s, peak RSS %M kB" $G run scenarios/$s.json --backend bvh --out /tmp/r_$s \
      > /tmp/$s.log 2>&1 || echo "$s exit $?" >> $OUT/runs.log
  grep -E "check|wall" /tmp/$s.log >> $OUT/runs.log || true
  summaries+=(/tmp/r_$s/summary.json)
done
for s in atrium atrium_1m; do
  python3 -c "
import json; d=json.load(open('scenarios/$s.json')); d.pop('\$schema'); d['name']='${s}_720p'
d['scene']['gltf']='$PWD/scenarios/'+d['scene']['gltf']; d['resolution']=[1280,720]; d['frames']=64
d['checks']=[{'name':'finite'}]; d.pop('capture', None)
json.dump(d, open('/tmp/${s}_720p.json','w'))"
  /usr/bin/time -f "${s}_720p wall %e s, peak RSS %M kB" $G run /tmp/${s}_720p.json --backend bvh --out /tmp/r_${s}_720p \
      > /tmp/${s}_720p.log 2>&1 || echo "${s}_720p exit $?" >> $OUT/runs.log
  grep -E "check|wall" /tmp/${s}_720p.log >> $OUT/runs.log || true
  summaries+=(/tmp/r_${s}_720p/summary.json)
done
python3 - "${summaries[@]}" <<'PY' > $OUT/h200-textured-scenes.json
import json, sys
rows = []
for f in sys.argv[1:]:
    try:
        s = json.load(open(f))
    except Exception as e:
        rows.append({"summary": f, "error": str(e)}); continue
    t = s.get("timings", {})
    passes = {name: p.get("median_ms") for name, p in t.get("passes", {}).items()}
    rows.append({"scenario": s["scenario"]["name"],
                 "verdict": s.get("verdict"), "device": s.get("device", {}).get("name"),
                 "resolution": s.get("resolved", {}).get("resolution"), "wall_seconds": s.get("wall_seconds"),
                 "checks": [{k: c.get(k) for k in ("name", "verdict", "message", "figures") if k in c} for c in s.get("checks", [])],
                 "frame_ms": t.get("frame"), "passes": passes})
print(json.dumps({"issue": 19, "command": "bash reports/benchmarks/h200-textured-scenes.sh (device machine, bundle of README.md)",
                  "rows": rows}, indent=1))
PY
cat $OUT/runs.log
