/* The plugin index: which node types each plugin file provides, remembered between runs so that
 * a command needing a few node types opens only their plugins (opening every plugin would bind
 * Embree, TBB, CHOLMOD and Assimp for a pipeline that uses none of them).
 *
 * One text file, by default $XDG_CACHE_HOME/rigflow/plugin-index ($RIGFLOW_PLUGIN_INDEX names
 * another; set empty, it turns the index off). A first line names the format and the host's ABI,
 * so another host ignores it; then one line per plugin file, tab-separated: path, device, inode,
 * size, modification and status-change times in nanoseconds, the plugin's id, its node types.
 * An entry counts only while the file's stat still matches: a rebuilt or replaced plugin is
 * opened again. The index never names a file to load: it only says which file on the search
 * path provides a type, and a file that does not keep that promise is opened with the rest.
 */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "rigflow-host.h"
#include "plugin-index.h"

#define RF_INDEX_MAGIC "rigflow-plugin-index 1"

void rf_index_entry_free(rf_index_entry *e)
{
    if (!e)
        return;
    g_free(e->path);
    g_free(e->id);
    g_strfreev(e->types);
    g_free(e);
}

char *rf_plugin_index_file(void)
{
    const char *env = g_getenv("RIGFLOW_PLUGIN_INDEX");
    if (env)
        return *env ? g_strdup(env) : NULL;
    return g_build_filename(g_get_user_cache_dir(), "rigflow", "plugin-index", NULL);
}

static gint64 stat_ns(struct timespec t)
{
    return (gint64)t.tv_sec * 1000000000 + t.tv_nsec;
}

bool rf_index_entry_matches(const rf_index_entry *e, const struct stat *st)
{
    return e->dev == (guint64)st->st_dev && e->ino == (guint64)st->st_ino &&
           e->size == (guint64)st->st_size && e->mtime_ns == stat_ns(st->st_mtim) &&
           e->ctime_ns == stat_ns(st->st_ctim);
}

static bool field_ok(const char *s)
{
    return s && *s && !strpbrk(s, "\t\n\r");
}

rf_index_entry *rf_index_entry_new(const char *path, const struct stat *st, const char *id,
                                   const char *const *types)
{
    if (!field_ok(path) || !field_ok(id))
        return NULL;
    for (const char *const *t = types; t && *t; t++)
        if (!field_ok(*t))
            return NULL;
    rf_index_entry *e = g_new0(rf_index_entry, 1);
    e->path = g_strdup(path);
    e->dev = (guint64)st->st_dev, e->ino = (guint64)st->st_ino, e->size = (guint64)st->st_size;
    e->mtime_ns = stat_ns(st->st_mtim), e->ctime_ns = stat_ns(st->st_ctim);
    e->id = g_strdup(id);
    e->types = types ? g_strdupv((char **)types) : g_new0(char *, 1);
    return e;
}

rf_index_entry *rf_index_entry_dup(const rf_index_entry *e)
{
    rf_index_entry *d = g_memdup2(e, sizeof *e);
    d->path = g_strdup(e->path);
    d->id = g_strdup(e->id);
    d->types = g_strdupv(e->types);
    return d;
}

static const char *index_header(char *buf, size_t size)
{
    rf_version v = RF_ABI_VERSION_INIT;
    snprintf(buf, size, "%s abi %u.%u.%u", RF_INDEX_MAGIC, v.major, v.minor, v.patch);
    return buf;
}

/* One line of the index, or NULL when it is not one. */
static rf_index_entry *parse_line(const char *line)
{
    g_auto(GStrv) f = g_strsplit(line, "\t", -1);
    if (g_strv_length(f) < 7)
        return NULL;
    char *end;
    guint64 num[5];
    for (int i = 0; i < 5; i++) {
        errno = 0;
        num[i] = g_ascii_strtoull(f[i + 1], &end, 10);
        if (errno || end == f[i + 1] || *end)
            return NULL;
    }
    rf_index_entry *e = g_new0(rf_index_entry, 1);
    e->path = g_strdup(f[0]);
    e->dev = num[0], e->ino = num[1], e->size = num[2];
    e->mtime_ns = (gint64)num[3], e->ctime_ns = (gint64)num[4];
    e->id = g_strdup(f[6]);
    e->types = g_strdupv(f + 7);
    return e;
}

GHashTable *rf_plugin_index_read(const char *file)
{
    GHashTable *entries =
        g_hash_table_new_full(g_str_hash, g_str_equal, NULL, (GDestroyNotify)rf_index_entry_free);
    g_autofree char *text = NULL;
    if (!file || !g_file_get_contents(file, &text, NULL, NULL))
        return entries;
    char header[96];
    index_header(header, sizeof header);
    g_auto(GStrv) lines = g_strsplit(text, "\n", -1);
    if (!lines[0] || strcmp(lines[0], header) != 0)
        return entries; /* another format or another host's ABI: start afresh */
    for (char **l = lines + 1; *l; l++) {
        rf_index_entry *e = **l ? parse_line(*l) : NULL;
        if (e)
            g_hash_table_replace(entries, e->path, e);
    }
    return entries;
}

static void append_entry(GString *out, const rf_index_entry *e)
{
    g_string_append_printf(out,
                           "%s\t%" G_GUINT64_FORMAT "\t%" G_GUINT64_FORMAT "\t%" G_GUINT64_FORMAT
                           "\t%" G_GINT64_FORMAT "\t%" G_GINT64_FORMAT "\t%s",
                           e->path, e->dev, e->ino, e->size, e->mtime_ns, e->ctime_ns, e->id);
    for (char **t = e->types; t && *t; t++)
        g_string_append_printf(out, "\t%s", *t);
    g_string_append_c(out, '\n');
}

/* Entries whose file is gone or changed are dropped, so the index does not grow with every
 * folder ever searched. Written to a temporary file and renamed: a reader sees the old index or
 * the new one; of two writers at once, one wins and the other's news is found again later. */
void rf_plugin_index_write(const char *file, GHashTable *entries)
{
    char header[96];
    g_autoptr(GString) out = g_string_new(index_header(header, sizeof header));
    g_string_append_c(out, '\n');
    g_autoptr(GList) paths = g_hash_table_get_keys(entries);
    paths = g_list_sort(paths, (GCompareFunc)strcmp);
    for (GList *l = paths; l; l = l->next) {
        const rf_index_entry *e = g_hash_table_lookup(entries, l->data);
        struct stat st;
        if (stat(e->path, &st) == 0 && rf_index_entry_matches(e, &st))
            append_entry(out, e);
    }
    g_autofree char *dir = g_path_get_dirname(file);
    if (g_mkdir_with_parents(dir, 0700) == 0)
        /* a cache: best effort */
        (void)g_file_set_contents(file, out->str, (gssize)out->len, NULL);
}
