# Reports: summaries printed for the user.
plugins_LTLIBRARIES += plugins/report.la
plugins_report_la_SOURCES = plugins/report/summary.c
plugins_report_la_LDFLAGS = $(PLUGIN_LDFLAGS)
