# Retargeting benchmark: bench/retarget/bench_retarget, built only by
# `make bench-retarget` (or `make bench`), and bench/retarget/run.sh, which runs it beside
# three.js retargetClip and the memory bandwidth floor, and compares quality on the same pairs.
EXTRA_PROGRAMS += bench/retarget/bench_retarget
bench_retarget_bench_retarget_SOURCES = bench/retarget/bench_retarget.c
bench_retarget_bench_retarget_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/retarget -I$(top_srcdir)/tests/retarget \
	 -I$(top_srcdir)/plugins/ik-twobone
bench_retarget_bench_retarget_LDADD = plugins/retarget/libretarget.la sdk/analysis/librigflow-analysis.la sdk/formats/bvh/librigflow-bvh.la \
	sdk/formats/assimp/librigflow-assimp.la plugins/ik-twobone/libiktwobone.la \
	sdk/ik/librigflow-ik.la -lm
CLEANFILES += bench/retarget/bench_retarget$(EXEEXT)
EXTRA_DIST += bench/retarget/run.sh bench/retarget/ratios.mjs bench/retarget/three_retarget.mjs \
	bench/retarget/pipeline.sh

bench-retarget: bench/retarget/bench_retarget$(EXEEXT)
	$(SHELL) $(srcdir)/bench/retarget/run.sh '$(abs_top_builddir)' $(BENCH_RETARGET_ARGS)
bench: bench-retarget
.PHONY: bench-retarget
