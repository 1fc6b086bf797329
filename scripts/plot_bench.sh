#!/usr/bin/env bash
# Plots a crowd_bench CSV with gnuplot (Debian package gnuplot-nox, installed if missing):
# frame time (max of CPU and GPU ms) against crowd size per path, and GPU time against bake error.
# Usage: scripts/plot_bench.sh CSV OUTDIR [scene, default field] [title] [lod mode, default distance]
# (CSVs from before LOD modes have no lod column; their rows are all plotted.)
set -euo pipefail
csv="$1"; out="$2"; scene="${3:-field}"; title="${4:-}"; lod="${5:-distance}"
if ! command -v gnuplot >/dev/null 2>&1; then
  echo "plot_bench: installing gnuplot-nox"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends gnuplot-nox
fi
mkdir -p "$out"
plots=""
for p in instanced compute gpu-culled gpu-driven gpu-culled-occlusion gpu-driven-occlusion traditional cpu rigid; do
  awk -F, -v s="$scene" -v p="$p" -v l="$lod" '$1=="paths" && $2==s && $3==p && ($15=="" || $15==l) {
      cpu = $8 + $9; print $4, (cpu > $10 ? cpu : $10) }' "$csv" > "$out/$p.dat"
  if [ -s "$out/$p.dat" ]; then
    plots="$plots${plots:+, }'$out/$p.dat' using 1:2 with linespoints lw 2 title '$p'"
  fi
done
awk -F, '$1=="error" { printf "%s %s %s@%s\n", $13, $10, $11, $12 }' "$csv" > "$out/error.dat"
gnuplot <<GP
set terminal png size 900,540
set grid
set output '$out/frame_time.png'
set logscale xy
set xlabel 'characters'
set ylabel 'max(CPU, GPU) ms per frame'
set title 'Frame time against crowd size, $scene scene $title'
set key left top
plot $plots
set output '$out/gpu_vs_error.png'
unset logscale y
set logscale x
set xlabel 'max vertex error of the bake (model units; the character is 2.05 units tall)'
set ylabel 'GPU ms per frame'
set title 'GPU time against bake error $title'
plot '$out/error.dat' using 1:2 with points pt 7 ps 1.5 notitle, \
     '$out/error.dat' using 1:2:3 with labels offset 0,1 font ',8' notitle
GP
echo "plot_bench: wrote $out/frame_time.png and $out/gpu_vs_error.png"
