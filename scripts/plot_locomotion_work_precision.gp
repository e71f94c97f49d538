# Locomotion smoothing and foot IK: error against run time, one panel per setting
# (scripts/accuracy; data from marionette_locomotion_work_precision). Each point is
# one value of the setting (labelled), pooled over the walk, run and mid-speed 5 m
# walks of RobotExpressive, joined in the order of the values. Errors share one
# log axis: foot skating in % of ground-contact frames, and planted-foot drift
# from the lock point in cm (all locks; the locks made at full gait weight). A
# zero is drawn at the axis floor. Cost differences under ~0.1 us are noise.
set datafile separator ","
set datafile missing NaN  # the rows of single gaits are skipped, the lines go on
set terminal pngcairo size 1350,840 font "sans,10"
set output "docs/work_precision_locomotion.png"
csv = "docs/data/locomotion_work_precision.csv"
floor = 0.05
atfloor(e) = (e > floor ? e : floor)
pooled(y) = (strcol(4) eq "all" ? atfloor(y) : NaN)
set logscale y
set yrange [floor:300]
set format y "%g"
set grid
set key top left font "sans,9" samplen 2 spacing 0.9 opaque
set multiplot layout 2,3 title "Locomotion on RobotExpressive (walk, run and mid speed, 5 m each): error against run time" font "sans,12"
array Title[6] = ["gait blend time constant (s; default 0.15)", "foot planting (0 off, 1 on; default on)", \
                  "contact height (m; default 0.06)", "release time (s; default 0.12)", \
                  "IK softness (default 0.05)", "frame step dt (s)"]
do for [i=0:5] {
  set title Title[i+1]
  if (i < 5) {
    unset logscale x
    set xlabel "locomotion controller, us per update (60 Hz)"
    xcol = 16
    # At least 0.4 us wide: a narrower axis would only spread the timing noise.
    stats csv index i using (strcol(4) eq "all" ? $16 : NaN) nooutput
    span = STATS_max - STATS_min > 0.4 ? STATS_max - STATS_min : 0.4
    centre = 0.5 * (STATS_max + STATS_min)
    set offsets 0, 0, 0, 0
    set xrange [centre - 0.62 * span : centre + 0.62 * span]
  } else {
    set logscale x
    set xlabel "locomotion controller, us per simulated second"
    set offsets graph 0.08, graph 0.08, 0, 0
    set autoscale x
    xcol = 17
  }
  if (i == 0) { set key } else { unset key }
  plot csv index i using xcol:(pooled($6)) with linespoints lw 1 pt 7 ps 1.1 lc rgb "#c0392b" title "skating (% of contact frames)", \
       csv index i using xcol:(pooled($6)):2 with labels left offset 0.8,0.5 font "sans,8" tc rgb "#c0392b" notitle, \
       csv index i using xcol:(pooled(100*$10)) with linespoints lw 1 dt 2 pt 6 ps 1.1 lc rgb "#7f8c8d" title "planted drift, all locks (cm)", \
       csv index i using xcol:(pooled(100*$11)) with linespoints lw 1 pt 9 ps 1.1 lc rgb "#2471a3" title "planted drift, locks at full gait (cm)", \
       csv index i using xcol:(pooled(100*$11)):2 with labels right offset -0.8,-0.5 font "sans,8" tc rgb "#2471a3" notitle
}
unset multiplot
