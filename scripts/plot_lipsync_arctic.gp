# Lip-sync curves of a real recorded line against its phone alignment (scripts/accuracy):
#   marionette lipsync --audio arctic_a0009.wav --phones arctic_a0009.phones.txt --visemes docs/data/lipsync_arctic_a0009.csv
# Columns: 1 time, 2 sil, 3 PP, 4 FF, 5 TH, 6 DD, 7 kk, 8 CH, 9 SS, 10 nn, 11 RR, 12 aa, 13 E, 14 ih,
# 15 oh, 16 ou, 17-21 vrm_*, 22 jawOpen. Phone boundaries from ../shared/assets/speech/arctic_a0009.phones.txt (CMU ARCTIC, never copied).
set datafile separator ","
set terminal pngcairo size 1400,520 font "sans,10"
set output "docs/lipsync_arctic_a0009.png"
set title "Lip-sync curves of CMU ARCTIC arctic_a0009 (\"He turned sharply, and faced Gregson across the table.\"), phone alignment as ground truth" noenhanced
set xlabel "time (s)"
set ylabel "channel weight"
set xrange [0:3.1]
set yrange [-0.12:1.05]
set key outside right top
set grid xtics
phones = "< grep -v '^#' ../shared/assets/speech/arctic_a0009.phones.txt | tr '\\t' ','"
# Phone labels under the axis, boundaries as thin lines.
set datafile commentschars "#"
plot phones using 1:(-0.05):(0):(1.1) with vectors nohead lc rgb "#cccccc" notitle, \
     phones using (($1+$2)/2):(-0.08):3 with labels font "sans,8" notitle, \
     "docs/data/lipsync_arctic_a0009.csv" using 1:3 with lines lw 3 lc rgb "#d62728" title "PP (lips closed)", \
     "" using 1:22 with lines lw 2 dt 2 lc rgb "black" title "jawOpen", \
     "" using 1:12 with lines lw 1.5 lc rgb "#ff7f0e" title "aa", \
     "" using 1:13 with lines lw 1.5 lc rgb "#2ca02c" title "E", \
     "" using 1:14 with lines lw 1.5 lc rgb "#1f77b4" title "ih", \
     "" using 1:15 with lines lw 1.5 lc rgb "#9467bd" title "oh", \
     "" using 1:16 with lines lw 1.5 lc rgb "#8c564b" title "ou", \
     "" using 1:4 with lines lw 1 lc rgb "#e377c2" title "FF", \
     "" using 1:5 with lines lw 1 lc rgb "#7f7f7f" title "TH", \
     "" using 1:6 with lines lw 1 lc rgb "#bcbd22" title "DD", \
     "" using 1:7 with lines lw 1 lc rgb "#17becf" title "kk", \
     "" using 1:8 with lines lw 1 lc rgb "#aec7e8" title "CH", \
     "" using 1:9 with lines lw 1 lc rgb "#ffbb78" title "SS", \
     "" using 1:10 with lines lw 1 lc rgb "#98df8a" title "nn", \
     "" using 1:11 with lines lw 1 lc rgb "#ff9896" title "RR"
