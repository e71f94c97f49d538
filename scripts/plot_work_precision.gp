# Error against run time for the clip optimizer's tolerance (scripts/accuracy).
# An exact result (error 0) is drawn at 1e-8 m, the floor of the log axis.
set datafile separator ","
set terminal pngcairo size 800,500 font "sans,11"
set output "docs/work_precision_clip_optimizer.png"
set title "Clip optimizer on the Pab walk, jog and crossarms: error against Sample1 cost"
set xlabel "Sample1 cost, microseconds per character (1000 characters, one core)"
set ylabel "max virtual-vertex error (m)"
set logscale y
set format y "1e%L"
set yrange [1e-8:1]
set grid
set key off
atfloor(e) = (e > 1e-8 ? e : 1e-8)
plot "docs/data/clip_optimizer_work_precision.csv" skip 1 using 6:(atfloor($3)) with linespoints lw 2 pt 7, \
     "" skip 1 using 6:(atfloor($3)):(sprintf("tol %g", $1)) with labels offset 0,1 font "sans,9"
