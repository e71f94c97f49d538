# Scaling of the runtime cost per character (from scripts/benchmarks: the median of the
# repetitions, the bars from the fastest to the slowest repetition).
set datafile separator ","
set terminal pngcairo size 800,500 font "sans,11"
set grid
set key off

set output "docs/scaling_joints.png"
set title "Cost per character against joint count (one clip, 100 characters, one core)"
set xlabel "joints"
set ylabel "microseconds per character per frame"
set logscale xy
plot "docs/data/scaling_joints.csv" skip 1 using 1:2:3:4 with yerrorlines lw 2 pt 7

set output "docs/scaling_characters.png"
set title "Cost per character against character count (RobotExpressive, 43 joints, one core)"
set xlabel "characters"
set logscale x
unset logscale y
set yrange [0:*]
plot "docs/data/scaling_characters.csv" skip 1 using 1:2:3:4 with yerrorlines lw 2 pt 7
