# Joint mapping speed: bench/match/bench_match, built only by `make bench-match` (or
# `make bench`); bench/match/run.sh runs it and `rigflow map --repeat` on the same pairs.
EXTRA_PROGRAMS += bench/match/bench_match
bench_match_bench_match_SOURCES = bench/match/bench_match.c tests/match/truth.c \
	tests/match/truth.h
bench_match_bench_match_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins \
	-I$(top_srcdir)/tests/match
bench_match_bench_match_LDADD = plugins/match-similarity/libsimilarity.la \
	sdk/analysis/librigflow-analysis.la sdk/formats/bvh/librigflow-bvh.la sdk/formats/assimp/librigflow-assimp.la -lm
CLEANFILES += bench/match/bench_match$(EXEEXT)
EXTRA_DIST += bench/match/run.sh

bench-match: bench/match/bench_match$(EXEEXT) rigflow$(EXEEXT) $(plugins_LTLIBRARIES)
	$(SHELL) $(srcdir)/bench/match/run.sh '$(abs_top_builddir)' $(BENCH_MATCH_ARGS)
bench: bench-match
.PHONY: bench-match
