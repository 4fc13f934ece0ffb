# The H200 measurement behind h200-equal-time.json: every realtime
# scenario of the default suite that has a reference check, run with
# --equal-time on the H200 (--backend bvh: its driver has no ray queries), so
# the realtime output, the GPU path tracer on the same GPU and Embree on the
# machine's 16 cores are measured at equal time. Run on the device machine
# from the project root with the bundle of README.md here in
# .devbundle/bundle.tgz (carry .devbundle):
#   cp reports/benchmarks/h200-equal-time.sh .devbundle/run.sh; bash .devbundle/run.sh
set -e
mkdir -p /tmp/b && tar -C /tmp/b -xzf .devbundle/bundle.tgz
export VK_ICD_FILENAMES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json LD_LIBRARY_PATH=/tmp/b/lib
G=/tmp/b/bin/giharness
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
summaries=()
for s in di_cornell_box di_cornell_exposure_quarter di_many_lights di_moving_occluder di_open_field_background \
         di_packing_range di_sun_penumbra gi_closed_room_reference gi_cornell_box gi_glossy_room gi_mirror; do
  /usr/bin/time -f "$s wall %e s" $G run scenarios/$s.json --backend bvh --equal-time --out /tmp/r_$s \
      > /tmp/$s.log 2>&1 || echo "$s exit $?"
  tail -1 /tmp/$s.log; cat /tmp/$s.log >> $OUT/runs.log
  summaries+=(/tmp/r_$s/summary.json)
done
python3 reports/benchmarks/equal_time_table.py --json $OUT/h200-equal-time.json "${summaries[@]}" | tee $OUT/table.md
# The same at 640x360, where the GPU is no longer idle between launches: the
# sweep puts both path tracers beside the realtime point (its own converged
# reference at 256 spp).
for s in di_many_lights gi_cornell_box; do
  /usr/bin/time -f "$s 640x360 wall %e s" $G sweep scenarios/$s.json --vary resolution=640x360 --reference-spp 256 \
      --out /tmp/sw_$s >> $OUT/runs.log 2>&1 || echo "sweep $s exit $?"
  python3 -c "
import json,sys; s=json.load(open('/tmp/sw_$s/sweep.json'))
for r in s['rows']: print('$s 640x360', r['kind'], r.get('spp'), round(r['ms_per_frame'],4), round(r['relmse'],5), r.get('equal_error_time_ratio_frame'), r.get('fits_budget'))
json.dump(s, open('$OUT/sweep_$s.json','w'), indent=1)"
done
# ReSTIR GI's knobs at 640x360 with the peers beside each point:
# initial samples (Solari: 1) by confidence cap (Solari: 8), and spatial tries.
$G sweep scenarios/gi_cornell_box.json --vary resolution=640x360 --reference-spp 256 --noise \
    --vary restir_gi.initial_samples=1,2,4,8 --vary restir_gi.confidence_cap=4,8,32 --out /tmp/knobs >> $OUT/runs.log 2>&1 \
    || echo "knob sweep exit $?"
python3 -c "
import json; s=json.load(open('/tmp/knobs/sweep.json'))
for r in s['rows']: r.pop('timings', None)
json.dump(s, open('$OUT/sweep_gi_knobs.json','w'), indent=1)"
