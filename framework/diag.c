/* Diagnostics: problems collected while loading plugins and validating pipelines, so every error
 * can be reported at once with the file, line, node and JSON pointer it concerns. */
#include <string.h>

#include <rigflow/text.h>

#include "pipeline-internal.h"

static void diag_free(gpointer data)
{
    rf_diag *d = data;
    g_free(d->file);
    g_free(d->node);
    g_free(d->pointer);
    g_free(d->message);
    g_free(d);
}

char *rf_printable(const char *text)
{
    size_t n = rf_text_escape(text, NULL, 0, RF_TEXT_KEEP_LINES);
    char *out = g_malloc(n + 1);
    rf_text_escape(text, out, n + 1, RF_TEXT_KEEP_LINES);
    return out;
}

GPtrArray *rf_diags_new(void)
{
    return g_ptr_array_new_with_free_func(diag_free);
}

void rf_diags_add(GPtrArray *diags, const char *file, int line, int column, const char *node,
                  const char *pointer, const char *fmt, ...)
{
    if (!diags)
        return;
    rf_diag *d = g_new0(rf_diag, 1);
    d->file = file ? rf_printable(file) : NULL;
    d->line = line;
    d->column = column;
    d->node = g_strdup(node);
    d->pointer = g_strdup(pointer);
    va_list ap;
    va_start(ap, fmt);
    g_autofree char *raw = g_strdup_vprintf(fmt, ap);
    va_end(ap);
    d->message = rf_printable(raw); /* messages quote bytes from files */
    g_ptr_array_add(diags, d);
}

char *rf_diag_format(const rf_diag *d)
{
    GString *s = g_string_new(NULL);
    if (d->file) {
        g_string_append(s, d->file);
        if (d->line > 0)
            g_string_append_printf(s, ":%d", d->line);
        if (d->column > 0)
            g_string_append_printf(s, ":%d", d->column);
        g_string_append(s, ": ");
    }
    if (d->node)
        g_string_append_printf(s, "node '%s': ", d->node);
    if (d->pointer)
        g_string_append_printf(s, "at %s: ", d->pointer);
    g_string_append(s, d->message);
    return g_string_free(s, FALSE);
}
