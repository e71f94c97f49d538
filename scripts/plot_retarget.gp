# Retargeting figures for docs/accuracy.md (data from marionette_retarget_work_precision).
set terminal pngcairo size 1200,900 font ",10" noenhanced
set datafile commentschars "#"

# 1. The CMU walk (131_01) as stick figures, side view, every 0.25 s from 2 s.
set output "docs/retarget_walk_strips.png"
set multiplot layout 5,1 title "CMU 131_01 walk retargeted (side view, character heights; a figure every 0.25 s)"
set size ratio -1
unset key
set xrange [-0.6:10.5]
set yrange [-0.05:1.15]
set ytics 0.5
names = "cmu_131_01_walk RobotExpressive Godette pab_arnaud CesiumMan"
do for [i=1:5] {
  n = word(names, i)
  set title n offset 0,-0.8
  plot "docs/data/retarget_strip_".n.".csv" using 2:3:4:5 with vectors nohead lw 1.5 lc rgb "#204080"
}
unset multiplot

# 2. Foot heights: the held foot stays down during contacts.
set output "docs/retarget_walk_feet.png"
set size noratio
set multiplot layout 2,1 title "Left foot height over the CMU walk (leg lengths above its lowest point)"
set xrange [0:8.3]
set yrange [-0.02:0.45]
set ytics auto
set key top right
set xlabel "time (s)"
set ylabel "height"
set title "source and targets, no IK"
plot "docs/data/retarget_feet_cmu_131_01_walk.csv" using 1:2 with lines lw 2 lc rgb "black" title "CMU source", \
     for [n in "RobotExpressive Godette pab_arnaud CesiumMan"] "docs/data/retarget_feet_".n.".csv" using 1:2 with lines title n
set title "targets with feet IK"
plot "docs/data/retarget_feet_cmu_131_01_walk.csv" using 1:2 with lines lw 2 lc rgb "black" title "CMU source", \
     for [n in "RobotExpressive Godette pab_arnaud CesiumMan"] "docs/data/retarget_feet_".n."_feet_ik.csv" using 1:2 with lines title n
unset multiplot

# 3. Work-precision: error against run time per frame, no IK / feet / feet and hands.
set output "docs/work_precision_retarget.png"
set terminal pngcairo size 1200,500 font ",10" noenhanced
set multiplot layout 1,2 title "Retargeting the CMU walk: error against run time (points: no IK, feet IK, feet and hands IK)"
set xlabel "run time per frame (us)"
set xrange [*:*]
set yrange [0:*]
set key top right
set ylabel "foot skating, output / source"
set title "foot skating during the source's contacts"
plot for [i=0:3] "docs/data/retarget_work_precision.dat" index i using 3:5 with linespoints pt 7 ps 1.2 title word("RobotExpressive Godette pab_arnaud CesiumMan", i+1)
set ylabel "end-effector error (fraction of height)"
set title "hands, feet, head relative to the hips"
plot for [i=0:3] "docs/data/retarget_work_precision.dat" index i using 3:4 with linespoints pt 7 ps 1.2 title word("RobotExpressive Godette pab_arnaud CesiumMan", i+1)
unset multiplot
