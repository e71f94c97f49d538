# PRT report (marionette prt report), 3: the work-precision diagram of PRT on RobotExpressive,
# shadowed. Rows: the light probes. Left: error against the precompute seconds of the whole mesh,
# one line per band count n, the points the ray counts N. Right: error against the per-frame
# relight time, one point per n at the largest N.
# gnuplot -e "data='docs/data/prt'; img='docs/img'" scripts/plot_prt_end_to_end.gp
if (!exists("data")) data = "docs/data/prt"
if (!exists("img")) img = "docs/img"
file = data."/end_to_end.csv"
maps = system("tail -n +2 '".file."' | cut -d, -f1 | uniq | tr '\\n' ' '")
maxN = int(system("tail -n +2 '".file."' | cut -d, -f3 | sort -n | tail -1"))
set datafile separator ","
set terminal pngcairo size 1200,900 font "sans,10"
set output img."/prt_end_to_end.png"
set multiplot layout words(maps),2 title "PRT on RobotExpressive (rest pose, shadowed) against ray-traced irradiance" noenhanced
set logscale xy
set format y "10^{%L}"
set grid
do for [i = 1:words(maps)] {
  m = word(maps, i)
  set title m." : error against precompute (points: N)" noenhanced
  set xlabel "precompute seconds, whole mesh"
  set ylabel "mean |E_{prt} - E_{ref}| / mean E_{ref} (worst channel)"
  set key outside right font "sans,9"
  plot for [n = 2:8] file skip 1 using ((strcol(1) eq m && $2 == n) ? $4 : NaN):12 \
       with linespoints lw 2 pt 7 ps 0.8 lc n title sprintf("n = %d", n)
  set title m.sprintf(" : error against relight cost (N = %d)", maxN) noenhanced
  set xlabel "relight microseconds per frame per 10k vertices"
  set key off
  plot file skip 1 using ((strcol(1) eq m && $3 == maxN) ? $5 : NaN):12 with linespoints lw 2 pt 7 lc rgb "black", \
       file skip 1 using ((strcol(1) eq m && $3 == maxN) ? $5 : NaN):12:(sprintf("n=%d", int($2))) with labels offset 0,1 font "sans,9"
}
unset multiplot
