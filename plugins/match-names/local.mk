# The "names" matcher plugin; name normalisation and matching are the SDK's (sdk/match), also
# linked by the skeletal-similarity plugin for strategy=names.
plugins_LTLIBRARIES += plugins/match-names.la
plugins_match_names_la_SOURCES = plugins/match-names/plugin.c
plugins_match_names_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_match_names_la_LIBADD = sdk/match/librigflow-match.la
