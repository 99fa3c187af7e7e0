# Fuzzing: libFuzzer harnesses built with clang, whatever compiler configure chose.
# `make fuzz FUZZ_SECONDS=N` builds each harness and runs it for N seconds on a scratch corpus
# (FUZZ_WORK, default $(abs_top_builddir)/fuzz-work; see tests/fuzz/fuzz.sh and doc/reliability.md).
FUZZ_SECONDS ?= 60
FUZZ_WORK ?= $(abs_top_builddir)/fuzz-work
FUZZ_ONLY ?=
CLANG ?= clang

# The pipeline harness loads the fixture plugin and the bundled plugins of this build.
fuzz: all tests/fixtures/fx_good.la
	RF_SRCDIR='$(abs_top_srcdir)' RF_BUILDDIR='$(abs_top_builddir)' RF_DATA_DIR='$(RF_DATA_DIR)' \
	FUZZ_SECONDS='$(FUZZ_SECONDS)' FUZZ_WORK='$(FUZZ_WORK)' FUZZ_ONLY='$(FUZZ_ONLY)' \
	CLANG='$(CLANG)' $(SHELL) $(abs_top_srcdir)/tests/fuzz/fuzz.sh
.PHONY: fuzz

EXTRA_DIST += tests/fuzz/fuzz.sh tests/fuzz/fuzz_bvh.c tests/fuzz/fuzz_pipeline.c tests/fuzz/fuzz-values.h \
	tests/fuzz/fuzz_analysis.c tests/fuzz/fuzz_mapping.c tests/fuzz/fuzz_ik.c tests/fuzz/fuzz_rig.c tests/fuzz/bvh.dict \
	tests/fuzz/pipeline.dict tests/fuzz/mapping.dict tests/fuzz/seeds
clean-local: clean-fuzz
clean-fuzz:
	rm -rf tests/fuzz/fuzz_bvh tests/fuzz/fuzz_pipeline tests/fuzz/fuzz_analysis \
		tests/fuzz/fuzz_mapping tests/fuzz/fuzz_ik tests/fuzz/fuzz_rig tests/fuzz/*.log
.PHONY: clean-fuzz
