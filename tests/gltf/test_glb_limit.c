/* GLB's length fields are uint32 (glTF 2.0, "Binary glTF Layout"): rf_gltf_glb_fits, which the
 * writer asks before it opens the file, fed sizes near the limit instead of writing 4 GiB. The
 * expected totals are worked out by hand: 12 (file header) + 8 (JSON chunk header) + the JSON
 * padded to 4 + 8 (binary chunk header) + the data padded to 4, the binary chunk only with data. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <rigflow/gltf-write.h>

static void small_files_fit(void **state)
{
    (void)state;
    char err[256] = "";
    assert_true(rf_gltf_glb_fits("a.glb", 0, 0, err, sizeof err));
    assert_true(rf_gltf_glb_fits("a.glb", 1000, 1 << 20, err, sizeof err));
    assert_string_equal(err, "");
}

/* The largest GLB is 4294967292 bytes (UINT32_MAX rounded down to 4): JSON 4 bytes, data
 * 4294967292 - 12 - 8 - 4 - 8 = 4294967260. One byte more of data pads to 4294967264 and the
 * file to 4294967296. */
static void the_limit_is_exact(void **state)
{
    (void)state;
    char err[256] = "";
    assert_true(rf_gltf_glb_fits("big.glb", 4, 4294967260u, err, sizeof err));
    assert_false(rf_gltf_glb_fits("big.glb", 4, 4294967261u, err, sizeof err));
    assert_non_null(strstr(err, "big.glb"));
    assert_non_null(strstr(err, "4294967296 bytes"));
    assert_non_null(strstr(err, "4294967295"));
    /* the JSON chunk counts as well: 12 + 8 + 4294967276 = 4294967296, no binary chunk */
    assert_true(rf_gltf_glb_fits("j.glb", 4294967272u, 0, err, sizeof err));
    assert_false(rf_gltf_glb_fits("j.glb", 4294967273u, 0, err, sizeof err));
}

/* Counts far past 32 bits (a 64-bit size_t from a huge buffer) are refused, not wrapped. */
static void huge_counts_do_not_wrap(void **state)
{
    (void)state;
    char err[256] = "";
    assert_false(rf_gltf_glb_fits("w.glb", 4, (uint64_t)1 << 32, err, sizeof err));
    assert_false(rf_gltf_glb_fits("w.glb", 4, ((uint64_t)1 << 32) + 4, err, sizeof err));
    assert_false(rf_gltf_glb_fits("w.glb", 4, UINT64_MAX, err, sizeof err));
    assert_false(rf_gltf_glb_fits("w.glb", UINT64_MAX - 2, 0, err, sizeof err));
    assert_non_null(strstr(err, "w.glb"));
    assert_false(rf_gltf_glb_fits(NULL, 4, UINT64_MAX, NULL, 0)); /* no message asked for */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(small_files_fit),
        cmocka_unit_test(the_limit_is_exact),
        cmocka_unit_test(huge_counts_do_not_wrap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
