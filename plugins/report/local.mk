# Reports: summaries printed for the user (report.summary) and the self-contained HTML page
# (report.html). The page's own script, style and markup are compiled in as C strings
# (report-assets.h, made from the files beside this one); three.js is read at report time from
# RF_THREE_DIR (configure --with-three).
plugins_LTLIBRARIES += plugins/report.la
plugins_report_la_SOURCES = plugins/report/summary.c plugins/report/html.c \
	plugins/report/html-out.h plugins/report/html-out.c
nodist_plugins_report_la_SOURCES = plugins/report/report-assets.h
plugins_report_la_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_builddir)/plugins/report
plugins_report_la_LDFLAGS = $(PLUGIN_LDFLAGS)
plugins_report_la_LIBADD = sdk/formats/gltf/librigflow-gltf.la sdk/analysis/librigflow-analysis.la \
	$(JANSSON_LIBS) -lm
BUILT_SOURCES += plugins/report/report-assets.h
CLEANFILES += plugins/report/report-assets.h
RF_REPORT_ASSETS = plugins/report/viewer.js plugins/report/viewer.css plugins/report/viewer.html
EXTRA_DIST += $(RF_REPORT_ASSETS) plugins/report/embed.sh

plugins/report/report-assets.h: $(RF_REPORT_ASSETS) plugins/report/embed.sh
	$(AM_V_GEN)$(MKDIR_P) plugins/report && \
	$(SHELL) $(srcdir)/plugins/report/embed.sh \
	  rf_report_viewer_js $(srcdir)/plugins/report/viewer.js \
	  rf_report_viewer_css $(srcdir)/plugins/report/viewer.css \
	  rf_report_viewer_html $(srcdir)/plugins/report/viewer.html >$@.tmp && mv $@.tmp $@
