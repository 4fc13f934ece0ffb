# An H200 record of a shader change, NAME.json (default h200-shader-restructure-ab): the
# bench scenes with the shaders of before (/tmp/b/shareA) and after (the bundle's
# share/giharness), alternated, three runs each. Run on the device machine from the
# project root with the bundle in .devbundle/bundle.tgz:
#   bash reports/benchmarks/h200-shader-restructure-ab.sh [NAME]
# shareA is the bundle's data folder with the before-files the bundle carries under
# before/ (their paths relative to the data folder) copied over it.
set -e
name=${1:-h200-shader-restructure-ab}
mkdir -p /tmp/b && tar -C /tmp/b -xzf .devbundle/bundle.tgz
if [ -d /tmp/b/before ]; then rm -rf /tmp/b/shareA && cp -r /tmp/b/share/giharness /tmp/b/shareA && cp -r /tmp/b/before/. /tmp/b/shareA/; fi
export VK_ICD_FILENAMES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json LD_LIBRARY_PATH=/tmp/b/lib
G=/tmp/b/bin/giharness
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
for i in 1 2 3; do for v in A B; do
  if [ $v = A ]; then D=/tmp/b/shareA; else D=/tmp/b/share/giharness; fi
  for s in full_cornell_1600x900 full_glossy_room_1600x900; do
    GIHARNESS_DATA_DIR=$D $G run scenarios/bench/$s.json --backend bvh --out /tmp/o/$v$i/$s > /tmp/o_${v}${i}_$s.log 2>&1 || echo "exit $? $v $s"
  done
done; done
NAME=$name python3 - <<'PY'
import json,statistics,os
out={}
for s in ['full_cornell_1600x900','full_glossy_room_1600x900']:
  for v in 'AB':
    per={}
    for i in '123':
      sm=json.load(open(f'/tmp/o/{v}{i}/{s}/summary.json'))
      for p,t in sm['timings']['passes'].items(): per.setdefault(p,[]).append(t['median_ms'])
      out.setdefault(s,{}).setdefault(v+'_hash',[]).append(sm['final_image_hash'])
    out[s][v]={p:statistics.median(x) for p,x in per.items()}
  print(s, 'hashes A', out[s]['A_hash'], 'B', out[s]['B_hash'])
  for p in sorted(out[s]['A'], key=lambda p:-out[s]['A'][p]):
    a=out[s]['A'][p]; b=out[s]['B'].get(p,0); print('  %-26s A %7.3f  B %7.3f  B/A %.3f'%(p,a,b,b/a if a else 0))
  print('  sum A %.3f B %.3f'%(sum(out[s]['A'].values()), sum(out[s]['B'].values())))
json.dump(out, open(os.environ['OUT']+'/'+os.environ['NAME']+'.json','w'), indent=1)
PY
