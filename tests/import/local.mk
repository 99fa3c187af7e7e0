# Import (Assimp) and glTF export tests: every model in $RF_DATA_DIR/models, GLB exports checked
# by the Khronos glTF-Validator (tests/gltf/validate.js; skipped without node or the package).
check_PROGRAMS += tests/import/test_import
TESTS += tests/import/test_import
tests_import_test_import_SOURCES = tests/import/test_import.c
tests_import_test_import_CPPFLAGS = $(AM_CPPFLAGS) -I$(top_srcdir)/tests/gltf -DRF_NODE='"$(NODE)"'
tests_import_test_import_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_import_test_import_LDADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la \
	$(CMOCKA_LIBS) -lm
EXTRA_DIST += tests/gltf/validate.js tests/gltf/validate.h tests/gltf/valid.sh tests/import/expected.py

# rigflow inspect: output and exit codes.
TESTS += tests/import/test_inspect.sh
EXTRA_DIST += tests/import/test_inspect.sh

# A BVH clip (libbvh) out as GLB, validated and read back through Assimp.
check_PROGRAMS += tests/import/test_bvh_gltf
TESTS += tests/import/test_bvh_gltf
tests_import_test_bvh_gltf_SOURCES = tests/import/test_bvh_gltf.c
tests_import_test_bvh_gltf_CPPFLAGS = $(tests_import_test_import_CPPFLAGS)
tests_import_test_bvh_gltf_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_import_test_bvh_gltf_LDADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la \
	sdk/formats/bvh/librigflow-bvh.la $(CMOCKA_LIBS) -lm

# GLB's uint32 size limit, checked before the writer opens the file.
check_PROGRAMS += tests/gltf/test_glb_limit
TESTS += tests/gltf/test_glb_limit
tests_gltf_test_glb_limit_SOURCES = tests/gltf/test_glb_limit.c
tests_gltf_test_glb_limit_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_gltf_test_glb_limit_LDADD = sdk/formats/gltf/librigflow-gltf.la $(CMOCKA_LIBS) -lm
check_PROGRAMS += tests/gltf/test_bone_mesh
TESTS += tests/gltf/test_bone_mesh
tests_gltf_test_bone_mesh_SOURCES = tests/gltf/test_bone_mesh.c plugins/convert/bone-mesh.c
tests_gltf_test_bone_mesh_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_gltf_test_bone_mesh_LDADD = $(CMOCKA_LIBS) -lm
# glTF's axes: a character declared Z-up or facing -Z written turned, read back through Assimp.
check_PROGRAMS += tests/gltf/test_gltf_axes
TESTS += tests/gltf/test_gltf_axes
tests_gltf_test_gltf_axes_SOURCES = tests/gltf/test_gltf_axes.c sdk/formats/gltf/gltf-axes.c
tests_gltf_test_gltf_axes_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_gltf_test_gltf_axes_LDADD = sdk/formats/assimp/librigflow-assimp.la sdk/formats/gltf/librigflow-gltf.la \
	$(CMOCKA_LIBS) -lm
# ... and when memory runs out at each of its allocations in turn (malloc and calloc wrapped)
check_PROGRAMS += tests/gltf/test_gltf_axes_oom
TESTS += tests/gltf/test_gltf_axes_oom
tests_gltf_test_gltf_axes_oom_SOURCES = tests/gltf/test_gltf_axes_oom.c sdk/formats/gltf/gltf-axes.c \
    tests/alloc-fail.h
tests_gltf_test_gltf_axes_oom_CFLAGS = $(AM_CFLAGS) $(CMOCKA_CFLAGS)
tests_gltf_test_gltf_axes_oom_LDFLAGS = -Wl,--wrap=malloc,--wrap=calloc
tests_gltf_test_gltf_axes_oom_LDADD = $(CMOCKA_LIBS) -lm

# pipelines/convert.json end to end (import and export nodes of plugins/convert).
TESTS += tests/import/test_convert.sh
EXTRA_DIST += tests/import/test_convert.sh
# its Assimp import loaded on first use only (plugins/convert/convert-assimp.c)
TESTS += tests/import/test_assimp_on_demand.sh
EXTRA_DIST += tests/import/test_assimp_on_demand.sh

# GLB exports keep the look and every clip: every model converted and retargeted, validated,
# counted against Assimp, read by three.js; bad textures left out with warnings.
TESTS += tests/gltf/test_export.sh
EXTRA_DIST += tests/gltf/test_export.sh tests/gltf/look.js tests/fixtures/textures/textured-sheet.gltf

# A GLB's binary chunk (its channels streamed into the file) against the .gltf's buffer.
TESTS += tests/gltf/test_glb_chunk.sh
EXTRA_DIST += tests/gltf/test_glb_chunk.sh

# Blender's glTF importer on the exports (one headless run, a few seconds).
TESTS += tests/gltf/test_blender.sh
EXTRA_DIST += tests/gltf/test_blender.sh tests/gltf/blender_check.py
