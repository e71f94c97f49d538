# Lip-sync curves: viseme onset error against run time (scripts/accuracy; data from
# marionette_lipsync_work_precision). Left: the curve sample rate (labelled, Hz)
# against the build time of 10 s of speech, mean and p95 |onset error| per ground
# truth. Right: the smoothing settings at 100 Hz, p95 |onset error| against how
# far each phoneme's viseme shows at its peak (mean over phonemes; 1 = neighbours
# do not blend in at all): what less co-articulation buys.
# The ground truths without rows (no espeak-ng in the build) draw nothing.
set datafile separator ","
set datafile missing NaN
set terminal pngcairo size 1300,520 font "sans,10"
set output "docs/work_precision_lipsync.png"
csv = "docs/data/lipsync_work_precision.csv"
floor = 2
atfloor(e) = (e > floor ? e : floor)
pick(set, src, y) = (strcol(1) eq set && strcol(3) eq src ? atfloor(y) : NaN)
array Src[3] = ["arctic_a0009", "espeak_175wpm", "espeak_300wpm"]
array Name[3] = ["ARCTIC a0009 (recorded)", "espeak-ng 175 wpm", "espeak-ng 300 wpm"]
set logscale y
set yrange [floor:200]
set format y "%g"
set grid
set key top left font "sans,9" samplen 2 spacing 0.9 opaque
set multiplot layout 1,2 title "Lip-sync curves: viseme onset error (ms) against run time" font "sans,12"
set title "curve sample rate (Hz), default settings otherwise"
set logscale x
set xlabel "build time of 10 s of speech (us, one core)"
set ylabel "|onset error| (ms)"
plot for [i=1:3] csv using 17:(pick("sampleRate", Src[i], $9)) with linespoints lw 2 pt 7 lc i title Name[i]." p95", \
     for [i=1:3] csv using 17:(pick("sampleRate", Src[i], $8)) with linespoints lw 1 dt 2 pt 6 lc i title Name[i]." mean", \
     csv using 17:(pick("sampleRate", Src[1], $9)):(sprintf("%g", $2)) with labels offset 0,1 font "sans,8" notitle
set title "smoothing settings (each alone; p95 |onset error|, all three ground truths)"
unset logscale x
set xrange [0.3:1]
set xlabel "mean peak of each phoneme's viseme (1 = no co-articulation)"
unset ylabel
array Set[4] = ["anticipationRate", "carryOverRate", "maxSpeed", "minVisible"]
array SetName[4] = ["anticipation rate (1/s)", "carry-over rate (1/s)", "speed limit (1/s; 0 none)", "min visible (s)"]
plot for [j=1:4] for [i=1:3] csv using 14:(pick(Set[j], Src[i], $9)) with linespoints lw (i == 1 ? 2 : 1) dt i pt 7 lc j \
       title (i == 1 ? SetName[j] : ""), \
     for [j=1:3] csv using 14:(pick(Set[j], Src[1], $9)):(sprintf("%g", $2)) with labels offset 0,1 font "sans,8" notitle
unset multiplot
