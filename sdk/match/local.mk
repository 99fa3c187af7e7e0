# Joint matching building blocks (rigflow/match-names.h: name normalisation and matching), used
# by the names matcher and by the similarity matcher's names strategy; installed (`rigflow-match`).
lib_LTLIBRARIES += sdk/match/librigflow-match.la
sdk_match_librigflow_match_la_SOURCES = sdk/match/names.c
sdk_match_librigflow_match_la_CFLAGS = $(AM_CFLAGS) $(SDK_LIB_CFLAGS)
sdk_match_librigflow_match_la_LDFLAGS = $(SDK_LIB_LDFLAGS)
rigflowinclude_HEADERS += sdk/include/rigflow/match-names.h
pkgconfig_DATA += sdk/rigflow-match.pc
