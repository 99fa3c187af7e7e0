/* The Khronos glTF-Validator from the C tests (tests/gltf/validate.js does the work; the shell
 * tests source tests/gltf/valid.sh). A missing validator is a visible skip, never a pass: each
 * check it could not make is counted, and the test program then exits 77 (automake's SKIP)
 * unless something failed. Include after cmocka.h. */
#ifndef RIGFLOW_TEST_GLTF_VALIDATE_H
#define RIGFLOW_TEST_GLTF_VALIDATE_H

#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>

static int rf_gltf_validations_skipped;

/* tests/gltf/validate.js on `file`: 0 valid, 1 errors (printed), 77 no node or validator. */
static inline int rf_gltf_validate(const char *file)
{
    const char *src = getenv("RF_SRCDIR");
    if (!src || !*RF_NODE)
        return 77;
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' '%s/tests/gltf/validate.js' '%s'", RF_NODE, src, file);
    FILE *p = popen(cmd, "r");
    if (!p)
        return 77;
    char line[1024];
    while (fgets(line, sizeof line, p))
        print_message("  %s", line);
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 1;
}

/* Fails the current test when the validator finds an error in `file`; counts a skip when there
 * is no validator. */
static inline void rf_gltf_check_valid(const char *file)
{
    int v = rf_gltf_validate(file);
    if (v == 77) {
        rf_gltf_validations_skipped++;
        print_message("SKIP: glTF-Validator not available (node or gltf-validator missing): %s "
                      "not validated\n",
                      file);
        return;
    }
    assert_int_equal(v, 0);
}

/* main's exit status: the failures, else 77 when a validation was skipped, else 0. */
static inline int rf_gltf_exit_status(int failed)
{
    if (failed)
        return failed;
    if (rf_gltf_validations_skipped)
        fprintf(stderr, "SKIP: %d glTF validations not made\n", rf_gltf_validations_skipped);
    return rf_gltf_validations_skipped ? 77 : 0;
}

#endif
