# The H200 record behind h200-museum-seeds.json and h200-suite-seeds.json:
# a suite at N seeds (nightly --seeds), split into shards that run side by
# side on the one GPU (--backend auto picks bvh: the driver has no ray
# queries) and merged. Run on the device machine from the project root with
# the bundle of README.md in .devbundle/bundle.tgz (carry .devbundle):
#   bash reports/benchmarks/h200-seeds.sh SUITE SEEDS SHARDS NAME
set -e
suite=$1 seeds=$2 shards=$3 name=$4
mkdir -p /tmp/b && tar -C /tmp/b -xzf .devbundle/bundle.tgz
# The generated atrium is git-ignored, so it does not travel with the tree.
[ -f scenarios/assets/generated/atrium_1m.glb ] || python3 scenarios/assets/make_atrium.py --triangles 1000000 \
  --materials 64 --glb --name atrium_1m --out scenarios/assets/generated > /dev/null
export VK_ICD_FILENAMES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json LD_LIBRARY_PATH=/tmp/b/lib
G=/tmp/b/bin/giharness
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | tee $OUT/$name.log
start=$(date +%s)
for i in $(seq 1 $shards); do
  $G nightly --suite $suite --seeds $seeds --shard $i/$shards --out /tmp/$name-shards/$i > /tmp/$name-shard-$i.log 2>&1 &
done
wait || true
$G merge /tmp/$name-shards/* --out /tmp/$name >> $OUT/$name.log 2>&1 || echo "merge exit $?" >> $OUT/$name.log
echo "wall $(( $(date +%s) - start )) s, $shards shards" >> $OUT/$name.log
cp /tmp/$name/summary.json $OUT/$name-summary.json || true
cp /tmp/$name/junit.xml $OUT/$name-junit.xml || true
for f in /tmp/$name-shard-*.log; do tail -n 60 $f; done >> $OUT/$name.log
