#!/bin/bash
# same_outputs.sh BIN OUTDIR [PREFIX...]: 11 sweeps and 3 reconstructions with BIN (PREFIX, e.g.
# `taskset -c 0`, before it); their observables.csv / reconstruction.csv and exit codes into OUTDIR.
# Compare two binaries or thread counts with `diff -r` (docs/folders.md).
BIN=$1; OUT=$2; shift 2
S=$(cd "$(dirname "$0")/.." && pwd)/scenes
mkdir -p $OUT; W=$(mktemp -d)
run() { name=$1; shift; "$@" $BIN sweep "${ARGS[@]}" --figures none --out $W/$name >/dev/null 2>$OUT/$name.err; echo "$name $?" >> $OUT/codes; [ -f $W/$name/observables.csv ] && cp $W/$name/observables.csv $OUT/$name.csv; }
for sc in c1-uniform-rigid-g1 c2-conical-g1 c3-elastic-support-g1 c4a-precurved-g1 c4b-precurved-g2 c5-tapered-precurved-elastic-g1 ge-experimental physical-beta-g1; do
  ARGS=($S/$sc.ron --points 60); run $sc "$@"
done
ARGS=(--profile g1 --q 5 --points 200); run g1-200 "$@"
ARGS=(--profile g2 --q 1 --a 2 --b 1 --points 60); run g2-precurved "$@"
ARGS=(--profile g1 --q 7.167 --theta 0.665 --a -0.691 --b 0.544 --alpha-deg -3.5 --points 60); run second-contact "$@"
for d in g1-200 c5-tapered-precurved-elastic-g1 second-contact; do
  "$@" $BIN reconstruct $W/$d --out $W/rec-$d >/dev/null 2>$OUT/rec-$d.err; echo "rec-$d $?" >> $OUT/codes
  [ -f $W/rec-$d/reconstruction.csv ] && cp $W/rec-$d/reconstruction.csv $OUT/rec-$d.csv
done
rm -rf $W
