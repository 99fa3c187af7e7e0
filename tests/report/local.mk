# report.html in a real browser: Debian's chromium driven by npm's playwright-core (tests/npm-tools.txt).
TESTS += tests/report/test_report_node.sh tests/report/test_report_browser.sh
# a node sending measures about any joint number (test_report_node.sh)
check_LTLIBRARIES += tests/report/fx_measures.la
tests_report_fx_measures_la_SOURCES = tests/report/fx_measures.c
tests_report_fx_measures_la_LDFLAGS = $(FIXTURE_LDFLAGS)
EXTRA_DIST += tests/report/test_report_node.sh tests/report/test_report_browser.sh tests/report/report-browser.mjs \
	tests/report/make-bvh.mjs
clean-local: clean-report-artefacts
clean-report-artefacts:
	-rm -rf tests/report/artefacts
.PHONY: clean-report-artefacts
