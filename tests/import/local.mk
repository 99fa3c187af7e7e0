# Import (Assimp) and glTF export tests: every model in $RF_DATA_DIR/models, GLB exports checked
# by the Khronos glTF-Validator (tests/gltf/validate.js; skipped without node or the package).
check_PROGRAMS += tests/import/test_import
TESTS += tests/import/test_import
tests_import_test_import_SOURCES = tests/import/test_import.c
tests_import_test_import_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/plugins/assimp \
	-I$(top_srcdir)/plugins/gltf -DRF_NODE='"$(NODE)"'
tests_import_test_import_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_import_test_import_LDADD = plugins/assimp/librfassimp.la plugins/gltf/librfgltf.la \
	$(CMOCKA_LIBS) -lm
EXTRA_DIST += tests/gltf/validate.js tests/import/expected.py

# rigflow inspect: output and exit codes.
TESTS += tests/import/test_inspect.sh
EXTRA_DIST += tests/import/test_inspect.sh
