# The "names" matcher: libnames (name normalisation and matching, also linked by the
# skeletal-similarity plugin for strategy=names) and the names plugin.
noinst_LTLIBRARIES += plugins/match-names/libnames.la
plugins_match_names_libnames_la_SOURCES = plugins/match-names/names.h plugins/match-names/names.c

plugins_LTLIBRARIES += plugins/match-names.la
plugins_match_names_la_SOURCES = plugins/match-names/plugin.c
plugins_match_names_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_match_names_la_LIBADD = plugins/match-names/libnames.la
