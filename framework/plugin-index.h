/* The plugin index (plugin-index.c): node types per plugin file, kept between runs. Internal to
 * librigflow. */
#ifndef RF_PLUGIN_INDEX_H
#define RF_PLUGIN_INDEX_H

#include <stdbool.h>
#include <sys/stat.h>

#include <glib.h>

typedef struct rf_index_entry {
    char *path;
    guint64 dev, ino, size;
    gint64 mtime_ns, ctime_ns;
    char *id;    /* the plugin's id */
    GStrv types; /* its node types; none for a file shadowed by an earlier plugin of that id */
} rf_index_entry;

/* The index file to use, or NULL when the index is turned off (g_free). */
char *rf_plugin_index_file(void);
/* path -> rf_index_entry* (owned by the table); empty when the file is missing or not one. */
GHashTable *rf_plugin_index_read(const char *file);
void rf_plugin_index_write(const char *file, GHashTable *entries);

/* NULL when a field could not be written on a line of its own (a tab or newline in it). */
rf_index_entry *rf_index_entry_new(const char *path, const struct stat *st, const char *id,
                                   const char *const *types);
rf_index_entry *rf_index_entry_dup(const rf_index_entry *e);
void rf_index_entry_free(rf_index_entry *e);
/* Whether the file is still the one the entry describes. */
bool rf_index_entry_matches(const rf_index_entry *e, const struct stat *st);

#endif
