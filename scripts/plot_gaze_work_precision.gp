# Gaze smoothing: error against run time per simulated second (scripts/accuracy).
# A diverged run (column 8 = 1, its error "inf") is drawn at the top of the axis, 1e3.
set datafile separator ","
set terminal pngcairo size 800,500 font "sans,11"
set output "docs/work_precision_gaze_smoothing.png"
set title "Gaze smoothing (critically damped, tau 0.12 s), moving target, frame steps 1/240 s to 0.5 s"
set xlabel "run time per simulated second (ns, one angle; larger = smaller frame step)"
set ylabel "max error against the reference (rad)"
set logscale xy
set format y "1e%L"
set yrange [1e-6:2e3]
set grid
set key top right
array T[4] = ["exact, target ramp (used)", "exact, target held", "semi-implicit Euler", "explicit Euler"]
plot for [i=0:3] "docs/data/gaze_smoothing_work_precision.csv" index i using 5:($8 > 0 ? 1e3 : $3) with linespoints lw 2 title T[i+1]
