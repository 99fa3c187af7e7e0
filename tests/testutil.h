/* Helpers shared by the host's cmocka tests. */
#ifndef RIGFLOW_TESTUTIL_H
#define RIGFLOW_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <glib/gstdio.h>
#include <sys/stat.h>

#include "rigflow-host.h"

/* The build tree's fixture plugin `name` (fx_good, fx_major, ...). (transfer full) */
static inline char *fixture_path(const char *name)
{
    const char *build = g_getenv("RF_BUILDDIR");
    g_autofree char *file = g_strdup_printf("%s.so", name);
    return g_build_filename(build ? build : ".", "tests", "fixtures", ".libs", file, NULL);
}

/* The diag whose formatted text contains every NULL-terminated needle, or NULL. Prints all diags
 * when none matches, so a failing test shows what was said instead. */
static inline const rf_diag *find_diag(const GPtrArray *diags, ...)
{
    for (guint i = 0; i < diags->len; i++) {
        const rf_diag *d = g_ptr_array_index((GPtrArray *)diags, i);
        g_autofree char *text = rf_diag_format(d);
        bool all = true;
        va_list ap;
        va_start(ap, diags);
        for (const char *s; all && (s = va_arg(ap, const char *));)
            all = strstr(text, s) != NULL;
        va_end(ap);
        if (all)
            return d;
    }
    for (guint i = 0; i < diags->len; i++) {
        g_autofree char *text = rf_diag_format(g_ptr_array_index((GPtrArray *)diags, i));
        print_message("  diag: %s\n", text);
    }
    return NULL;
}

#endif
