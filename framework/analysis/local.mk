# Skeleton analysis: a convenience library linked statically into the matchers, the
# retargeters and the riggers. It needs only the SDK headers and libm.
noinst_LTLIBRARIES += framework/analysis/libanalysis.la
framework_analysis_libanalysis_la_SOURCES = \
	framework/analysis/analysis.h \
	framework/analysis/analysis-internal.h \
	framework/analysis/analysis.c \
	framework/analysis/geom.c \
	framework/analysis/symmetry.c \
	framework/analysis/axes.c \
	framework/analysis/body.c \
	framework/analysis/sections.c \
	framework/analysis/measure.c \
	framework/analysis/pose.c \
	framework/analysis/roles.c
framework_analysis_libanalysis_la_CFLAGS = $(AM_CFLAGS)
framework_analysis_libanalysis_la_LIBADD = -lm

