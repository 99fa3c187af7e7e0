# Reliability: the bad-input matrix, the sanitizer check, and `make valgrind`.
# doc/reliability.md says what each guarantees and what the runs found.
check_LTLIBRARIES += tests/reliability/fx_overflow.la
tests_reliability_fx_overflow_la_SOURCES = tests/reliability/fx_overflow.c
tests_reliability_fx_overflow_la_LDFLAGS = $(FIXTURE_LDFLAGS)

TESTS += tests/reliability/test_bad_input.sh tests/reliability/test_sanitizers.sh tests/reliability/test_lsan_retry.sh
dist_noinst_SCRIPTS += tests/reliability/test_bad_input.sh tests/reliability/test_sanitizers.sh \
	tests/reliability/valgrind.sh tests/reliability/bench_memory.sh tests/reliability/lsan-retry.sh \
	tests/reliability/test_lsan_retry.sh
# In the sanitizer build every test runs through lsan-retry.sh, which reruns a test once when
# LeakSanitizer's own tracer crashed at exit (no leak looked at), and never otherwise.
if SANITIZERS
LOG_COMPILER = $(SHELL) $(abs_top_srcdir)/tests/reliability/lsan-retry.sh
endif
EXTRA_DIST += tests/reliability/valgrind.supp

# The end-to-end tests again, with every rigflow command under valgrind memcheck: any invalid
# read or write, use of uninitialised memory or definite leak fails the run (tests/reliability/
# valgrind.sh). Deep-nesting rows use 10 000 joints there: valgrind is ~50 times slower.
VALGRIND_TESTS = tests/test_cli.sh tests/reliability/test_bad_input.sh
VALGRIND_TESTS += tests/batch/test_batch.sh
valgrind: all $(check_LTLIBRARIES)
	@rm -rf '$(abs_top_builddir)/valgrind-logs'; \
	fail=0; for t in $(VALGRIND_TESTS); do \
	  echo "== valgrind: $$t"; \
	  $(AM_TESTS_ENVIRONMENT) RF_RIGFLOW='$(abs_top_srcdir)/tests/reliability/valgrind.sh' \
	  RF_VG_LOGS='$(abs_top_builddir)/valgrind-logs' RF_DEEP_JOINTS=10000 \
	  $(SHELL) $(abs_top_srcdir)/$$t || fail=1; \
	done; \
	RF_VG_LOGS='$(abs_top_builddir)/valgrind-logs' $(SHELL) \
	  $(abs_top_srcdir)/tests/reliability/valgrind.sh --summary || fail=1; \
	exit $$fail
.PHONY: valgrind
clean-local: clean-valgrind
clean-valgrind:
	rm -rf valgrind-logs
.PHONY: clean-valgrind

# Peak RSS importing a generated 100 MiB BVH, beside the motion's own size (doc/reliability.md).
bench-memory: all
	$(AM_TESTS_ENVIRONMENT) $(SHELL) $(abs_top_srcdir)/tests/reliability/bench_memory.sh
.PHONY: bench-memory
