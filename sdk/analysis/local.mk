# Skeleton analysis (rigflow/analysis.h): an installed SDK library, so matchers, retargeters and
# riggers built in or out of tree share it (`pkg-config --libs rigflow-analysis`). Built static
# and position-independent: each plugin links its own copy and needs nothing at run time but libm.
lib_LTLIBRARIES += sdk/analysis/librigflow-analysis.la
sdk_analysis_librigflow_analysis_la_SOURCES = \
	sdk/analysis/analysis-internal.h \
	sdk/analysis/analysis.c \
	sdk/analysis/geom.c \
	sdk/analysis/symmetry.c \
	sdk/analysis/axes.c \
	sdk/analysis/body.c \
	sdk/analysis/sections.c \
	sdk/analysis/measure.c \
	sdk/analysis/pose.c \
	sdk/analysis/roles.c
sdk_analysis_librigflow_analysis_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS)
sdk_analysis_librigflow_analysis_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
sdk_analysis_librigflow_analysis_la_LIBADD = -lm
rigflowinclude_HEADERS += sdk/include/rigflow/analysis.h
pkgconfig_DATA += sdk/rigflow-analysis.pc
