/* Plugin loading and the registry of node types.
 *
 * A plugin is opened with every symbol resolved at once, so an unresolved symbol refuses the
 * plugin at load instead of crashing a run later: libltdl's dlopen loader binds lazily and offers
 * no advice for eager binding, so the file is first probed with dlopen(RTLD_NOW | RTLD_LOCAL),
 * which binds it, and then opened through libltdl, which shares that loaded object.
 */
#include <dlfcn.h>
#include <errno.h>
#include <ltdl.h>
#include <string.h>
#include <sys/stat.h>

#include "plugin-index.h"
#include "rigflow-host.h"

struct rf_plugin {
    char *path;
    lt_dlhandle handle;
    const rf_plugin_entry *raw;   /* the plugin's own entry, in the layout it was built with */
    const rf_plugin_entry *entry; /* the same in this build's layout (see normalise), or NULL */
    rf_plugin_entry copy;         /* what `entry` points to once normalised */
    GPtrArray *owned;             /* the normalised descriptors and their arrays (g_free) */
    guint seq;                    /* its file's place on the search path */
};

/* A plugin file the index vouches for, not opened yet (lazy loading). */
typedef struct rf_pending {
    rf_index_entry *entry;
    guint seq;
    bool done; /* opened since (or tried) */
} rf_pending;

struct rf_registry {
    GPtrArray *plugins; /* rf_plugin*, in search-path order */
    GHashTable *types;  /* node type id -> rf_plugin* (borrowed) */
    guint seq;          /* search-path place of the next file */
    /* Lazy loading (rf_registry_set_lazy): files known from the index wait here until one of
     * their node types is asked for, or every plugin is listed. To everything else (shadowing,
     * duplicate types) they count as loaded, so the answers are those of loading everything. */
    bool lazy;
    GPtrArray *pending;        /* rf_pending*, in search-path order */
    GHashTable *pending_types; /* node type -> rf_pending* (borrowed) */
    GHashTable *pending_ids;   /* plugin id -> rf_pending* (borrowed) */
    GPtrArray *late;           /* refusals met while opening them */
    GRecMutex lock;            /* opening them changes a registry callers treat as read-only */
};

/* libltdl keeps process-wide state and is not thread-safe: this lock and its init count are the
 * only globals of the host. */
static GMutex ltdl_lock;
static int ltdl_users;

rf_registry *rf_registry_new(void)
{
    g_mutex_lock(&ltdl_lock);
    if (ltdl_users++ == 0)
        lt_dlinit();
    g_mutex_unlock(&ltdl_lock);
    rf_registry *reg = g_new0(rf_registry, 1);
    reg->plugins = g_ptr_array_new();
    reg->types = g_hash_table_new(g_str_hash, g_str_equal);
    reg->pending = g_ptr_array_new();
    reg->pending_types = g_hash_table_new(g_str_hash, g_str_equal);
    reg->pending_ids = g_hash_table_new(g_str_hash, g_str_equal);
    reg->late = rf_diags_new();
    g_rec_mutex_init(&reg->lock);
    return reg;
}

static void plugin_unload(rf_plugin *p, bool deinit)
{
    if (p->owned)
        g_ptr_array_free(p->owned, TRUE);
    if (deinit && p->entry && p->entry->deinit)
        p->entry->deinit();
    if (p->handle) {
        g_mutex_lock(&ltdl_lock);
        lt_dlclose(p->handle);
        g_mutex_unlock(&ltdl_lock);
    }
    g_free(p->path);
    g_free(p);
}

void rf_registry_free(rf_registry *reg)
{
    if (!reg)
        return;
    for (guint i = reg->plugins->len; i-- > 0;)
        plugin_unload(g_ptr_array_index(reg->plugins, i), true);
    g_ptr_array_free(reg->plugins, TRUE);
    g_hash_table_destroy(reg->types);
    for (guint i = 0; i < reg->pending->len; i++) {
        rf_pending *d = g_ptr_array_index(reg->pending, i);
        rf_index_entry_free(d->entry);
        g_free(d);
    }
    g_ptr_array_free(reg->pending, TRUE);
    g_hash_table_destroy(reg->pending_types);
    g_hash_table_destroy(reg->pending_ids);
    g_ptr_array_free(reg->late, TRUE);
    g_rec_mutex_clear(&reg->lock);
    g_free(reg);
    g_mutex_lock(&ltdl_lock);
    if (--ltdl_users == 0)
        lt_dlexit();
    g_mutex_unlock(&ltdl_lock);
}

/* Opens the file with every symbol bound. Returns NULL and sets *why on failure. */
static lt_dlhandle open_bound(const char *path, char **why)
{
    void *probe = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!probe) {
        const char *e = dlerror();
        *why = g_strdup(e ? e : "unknown dlopen error");
        return NULL;
    }
    g_mutex_lock(&ltdl_lock);
    lt_dladvise advise;
    lt_dladvise_init(&advise);
    lt_dladvise_local(&advise);
    lt_dlhandle h = lt_dlopenadvise(path, advise);
    if (!h) {
        const char *e = lt_dlerror(); /* copied at once: the next libltdl call overwrites it */
        *why = g_strdup(e ? e : "unknown libltdl error");
    }
    lt_dladvise_destroy(&advise);
    g_mutex_unlock(&ltdl_lock);
    dlclose(probe);
    return h;
}

/* Normalisation: every descriptor a plugin gives is copied into a zeroed struct of this build,
 * min(its size, ours) bytes, so fields appended after the plugin was built read as zero and the
 * rest of the host never looks at the plugin's own layout. A size below the struct's 1.0 layout,
 * or beyond any layout this ABI could reach, is refused. */
#define RF_MAX_STRUCT_SIZE 65536u

static bool size_ok(uint32_t size, size_t min, const char *what, GString *why)
{
    if (size >= min && size <= RF_MAX_STRUCT_SIZE)
        return true;
    g_string_append_printf(why, "%s declares size %u; ABI 1.x needs %zu to %u bytes", what, size,
                           min, RF_MAX_STRUCT_SIZE);
    return false;
}

/* `src`'s first min(size, dst_size) bytes into a zeroed `dst`, whose uint32_t size field at
 * `size_at` then says what it now is: a struct of this build. */
static void copy_prefix(void *dst, size_t dst_size, const void *src, uint32_t size, size_t size_at)
{
    memset(dst, 0, dst_size);
    memcpy(dst, src, MIN((size_t)size, dst_size));
    uint32_t ours = (uint32_t)dst_size;
    memcpy((char *)dst + size_at, &ours, sizeof ours);
}

/* A plugin's array of `n` elements, each starting with its own size, walked by those sizes and
 * copied into an array of this build's elements (`elem` bytes each). NULL after saying why. */
static void *copy_array(rf_plugin *p, const void *raw, uint32_t n, size_t elem, size_t min,
                        const char *what, GString *why)
{
    char *out = g_malloc0(elem * (n ? n : 1));
    g_ptr_array_add(p->owned, out);
    const char *at = raw;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t size;
        memcpy(&size, at, sizeof size);
        if (!size_ok(size, min, what, why))
            return NULL;
        if (size % sizeof(void *) != 0) {
            g_string_append_printf(why, "%s declares size %u, not a whole array element", what,
                                   size);
            return NULL;
        }
        copy_prefix(out + i * elem, elem, at, size, 0);
        at += size;
    }
    return out;
}

static bool port_ok(const rf_port_desc *p, GString *why)
{
    if (!p->name || !p->type) {
        g_string_append_printf(why, "a port lacks its name or type");
        return false;
    }
    return true;
}

static bool param_ok(const rf_param_desc *p, GString *why)
{
    if (!p->name) {
        g_string_append(why, "a parameter lacks its name");
        return false;
    }
    if (p->type < RF_PARAM_BOOL || p->type > RF_PARAM_OUTPUT_PATH) {
        g_string_append_printf(why, "parameter '%s' has unknown type %u", p->name, p->type);
        return false;
    }
    if (p->type == RF_PARAM_ENUM && !p->choices) {
        g_string_append_printf(why, "enum parameter '%s' lists no choices", p->name);
        return false;
    }
    return true;
}

/* One node descriptor and its port and parameter arrays in this build's layout, checked
 * complete enough to be driven; NULL after saying why. */
static rf_node_desc *normalise_node(rf_plugin *p, const rf_node_desc *raw, GString *why)
{
    if (!raw || !size_ok(raw->size, RF_NODE_DESC_SIZE_1_0, "a node type", why))
        return NULL;
    rf_node_desc *d = g_malloc(sizeof *d);
    g_ptr_array_add(p->owned, d);
    copy_prefix(d, sizeof *d, raw, raw->size, offsetof(rf_node_desc, size));
    if (!d->type || !d->process) {
        g_string_append(why, "a node type lacks its type id or process function");
        return NULL;
    }
    if ((d->input_count && !d->inputs) || (d->output_count && !d->outputs) ||
        (d->param_count && !d->params)) {
        g_string_append_printf(why, "node type '%s' counts ports or params it does not list",
                               d->type);
        return NULL;
    }
    d->inputs = copy_array(p, raw->inputs, d->input_count, sizeof(rf_port_desc),
                           RF_PORT_DESC_SIZE_1_0, "a port", why);
    d->outputs = d->inputs ? copy_array(p, raw->outputs, d->output_count, sizeof(rf_port_desc),
                                        RF_PORT_DESC_SIZE_1_0, "a port", why)
                           : NULL;
    d->params = d->outputs ? copy_array(p, raw->params, d->param_count, sizeof(rf_param_desc),
                                        RF_PARAM_DESC_SIZE_1_0, "a parameter", why)
                           : NULL;
    if (!d->params)
        return NULL;
    for (uint32_t i = 0; i < d->input_count; i++)
        if (!port_ok(&d->inputs[i], why))
            return NULL;
    for (uint32_t i = 0; i < d->output_count; i++)
        if (!port_ok(&d->outputs[i], why))
            return NULL;
    for (uint32_t i = 0; i < d->param_count; i++)
        if (!param_ok(&d->params[i], why))
            return NULL;
    return d;
}

/* The plugin's entry and every descriptor under it in this build's layout (p->entry). */
static bool normalise(rf_plugin *p, GString *why)
{
    const rf_plugin_entry *raw = p->raw;
    if (!size_ok(raw->size, RF_PLUGIN_ENTRY_SIZE_1_0, "its entry", why))
        return false;
    copy_prefix(&p->copy, sizeof p->copy, raw, raw->size, offsetof(rf_plugin_entry, size));
    rf_plugin_entry *e = &p->copy;
    if (!e->id || !e->name) {
        g_string_append(why, "its entry lacks its id or name");
        return false;
    }
    if (e->node_count && !e->nodes) {
        g_string_append(why, "its entry counts node types it does not list");
        return false;
    }
    const rf_node_desc **nodes = g_new0(const rf_node_desc *, e->node_count ? e->node_count : 1);
    g_ptr_array_add(p->owned, nodes);
    for (uint32_t i = 0; i < e->node_count; i++)
        if (!(nodes[i] = normalise_node(p, raw->nodes[i], why)))
            return false;
    e->nodes = nodes;
    p->entry = e;
    return true;
}

/* A node type `e` lists twice, or NULL: the registry maps a type to its plugin and finds the
 * first descriptor of that type, so the second would never run and nobody would be told. */
static const char *type_twice(const rf_plugin_entry *e)
{
    for (uint32_t i = 0; i < e->node_count; i++)
        for (uint32_t k = 0; k < i; k++)
            if (strcmp(e->nodes[i]->type, e->nodes[k]->type) == 0)
                return e->nodes[i]->type;
    return NULL;
}

/* The path of the plugin, loaded or waiting, that provides one of `e`'s node types, or NULL. */
static const char *type_clash(rf_registry *reg, const rf_plugin_entry *e, const char **type)
{
    for (uint32_t i = 0; i < e->node_count; i++) {
        rf_plugin *other = g_hash_table_lookup(reg->types, e->nodes[i]->type);
        rf_pending *waiting = g_hash_table_lookup(reg->pending_types, e->nodes[i]->type);
        if (other || waiting) {
            *type = e->nodes[i]->type;
            return other ? other->path : waiting->entry->path;
        }
    }
    return NULL;
}

static bool id_known(rf_registry *reg, const char *id)
{
    for (guint i = 0; id && i < reg->plugins->len; i++)
        if (strcmp(((rf_plugin *)g_ptr_array_index(reg->plugins, i))->entry->id, id) == 0)
            return true;
    return id && g_hash_table_contains(reg->pending_ids, id);
}

static bool already_loaded(rf_registry *reg, const rf_plugin_entry *e)
{
    for (guint i = 0; i < reg->plugins->len; i++)
        if (((rf_plugin *)g_ptr_array_index(reg->plugins, i))->raw == e)
            return true;
    return id_known(reg, e->id);
}

/* The ABI, descriptor and init checks on an opened plugin. Returns false with a diag. */
static bool admit(rf_registry *reg, rf_plugin *p, GPtrArray *diags)
{
    const rf_plugin_entry *e = p->raw;
    rf_version host = RF_ABI_VERSION_INIT;
    if (!rf_version_compatible(host, e->abi)) {
        rf_diags_add(diags, p->path, 0, 0, NULL, NULL,
                     "incompatible plugin ABI: the plugin was built for ABI %u.%u.%u, this host "
                     "implements %u.%u.%u (a plugin needs the same major and a minor no greater "
                     "than the host's)",
                     e->abi.major, e->abi.minor, e->abi.patch, host.major, host.minor, host.patch);
        return false;
    }
    g_autoptr(GString) why = g_string_new(NULL);
    if (!normalise(p, why)) {
        rf_diags_add(diags, p->path, 0, 0, NULL, NULL, "malformed rigflow plugin: %s", why->str);
        return false;
    }
    e = p->entry;
    const char *type = type_twice(e);
    if (type) {
        rf_diags_add(diags, p->path, 0, 0, NULL, NULL,
                     "malformed rigflow plugin: it lists node type '%s' twice", type);
        return false;
    }
    const char *other = type_clash(reg, e, &type);
    if (other) {
        rf_diags_add(diags, p->path, 0, 0, NULL, NULL,
                     "duplicate node type '%s': already provided by %s", type, other);
        return false;
    }
    char err[512] = "";
    if (e->init && !e->init(rf_host_table(), err, sizeof err)) {
        err[sizeof err - 1] = '\0';
        rf_diags_add(diags, p->path, 0, 0, NULL, NULL, "plugin failed to initialise: %s",
                     err[0] ? err : "(the plugin gave no reason)");
        return false;
    }
    return true;
}

/* In search-path order whatever order the files were opened in. */
static void add_plugin(rf_registry *reg, rf_plugin *p)
{
    guint at = reg->plugins->len;
    while (at > 0 && ((rf_plugin *)g_ptr_array_index(reg->plugins, at - 1))->seq > p->seq)
        at--;
    g_ptr_array_insert(reg->plugins, (gint)at, p);
    for (uint32_t i = 0; i < p->entry->node_count; i++)
        g_hash_table_insert(reg->types, (gpointer)p->entry->nodes[i]->type, p);
}

/* rf_registry_load_file for the file at search-path place `seq`; *shadow (may be NULL) gets the
 * id of a plugin shadowed by an earlier one of that id (g_free). */
static bool load_file_at(rf_registry *reg, const char *path, GPtrArray *diags, guint seq,
                         char **shadow)
{
    char *why = NULL;
    lt_dlhandle h = open_bound(path, &why);
    if (!h) {
        rf_diags_add(diags, path, 0, 0, NULL, NULL, "cannot load plugin: %s", why);
        g_free(why);
        return false;
    }
    rf_plugin *p = g_new0(rf_plugin, 1);
    p->path = g_strdup(path);
    p->handle = h;
    g_mutex_lock(&ltdl_lock);
    p->raw = lt_dlsym(h, "rigflow_plugin_entry");
    g_mutex_unlock(&ltdl_lock);
    p->owned = g_ptr_array_new_with_free_func(g_free);
    if (!p->raw) {
        rf_diags_add(diags, path, 0, 0, NULL, NULL,
                     "not a rigflow plugin: it does not export the symbol %s",
                     RF_PLUGIN_ENTRY_SYMBOL);
        plugin_unload(p, false);
        return false;
    }
    if (already_loaded(reg, p->raw)) { /* the same plugin later on the search path: shadowed */
        if (shadow && p->raw->id)
            *shadow = g_strdup(p->raw->id);
        plugin_unload(p, false);
        return true;
    }
    if (!admit(reg, p, diags)) {
        plugin_unload(p, false);
        return false;
    }
    p->seq = seq;
    add_plugin(reg, p);
    return true;
}

bool rf_registry_load_file(rf_registry *reg, const char *path, GPtrArray *diags)
{
    g_rec_mutex_lock(&reg->lock);
    bool ok = load_file_at(reg, path, diags, reg->seq++, NULL);
    g_rec_mutex_unlock(&reg->lock);
    return ok;
}

/* ---- lazy loading ---- */

void rf_registry_set_lazy(rf_registry *reg, bool lazy)
{
    reg->lazy = lazy;
}

static void open_pending(rf_registry *reg, rf_pending *d)
{
    if (d->done)
        return;
    d->done = true;
    for (char **t = d->entry->types; *t; t++)
        if (g_hash_table_lookup(reg->pending_types, *t) == d)
            g_hash_table_remove(reg->pending_types, *t);
    if (g_hash_table_lookup(reg->pending_ids, d->entry->id) == d)
        g_hash_table_remove(reg->pending_ids, d->entry->id);
    load_file_at(reg, d->entry->path, reg->late, d->seq, NULL);
}

/* Every plugin still waiting, in search-path order: for whoever walks the whole registry. */
static void open_all(const rf_registry *creg)
{
    rf_registry *reg = (rf_registry *)creg; /* loading adds answers, changes none given */
    g_rec_mutex_lock(&reg->lock);
    for (guint i = 0; i < reg->pending->len; i++)
        open_pending(reg, g_ptr_array_index(reg->pending, i));
    g_rec_mutex_unlock(&reg->lock);
}

void rf_registry_take_diags(rf_registry *reg, GPtrArray *diags)
{
    g_rec_mutex_lock(&reg->lock);
    while (reg->late->len)
        g_ptr_array_add(diags, g_ptr_array_steal_index(reg->late, 0));
    g_rec_mutex_unlock(&reg->lock);
}

/* Leaves the file unopened when its index entry `e` (current) says enough: its plugin is then
 * shadowed by an earlier one of its id, or waits for one of its types to be asked for. False
 * when it must be opened now: a record of a shadowed file whose shadow is gone, or a type that
 * an earlier plugin provides too (opened, it is refused with the usual message). */
static bool defer(rf_registry *reg, const rf_index_entry *e)
{
    if (id_known(reg, e->id))
        return true;
    if (!e->types[0])
        return false;
    for (char **t = e->types; *t; t++)
        if (g_hash_table_contains(reg->types, *t) || g_hash_table_contains(reg->pending_types, *t))
            return false;
    rf_pending *d = g_new0(rf_pending, 1);
    d->entry = rf_index_entry_dup(e);
    d->seq = reg->seq++;
    g_ptr_array_add(reg->pending, d);
    g_hash_table_insert(reg->pending_ids, d->entry->id, d);
    for (char **t = d->entry->types; *t; t++)
        g_hash_table_insert(reg->pending_types, *t, d);
    return true;
}

/* One file of the search path with the index at hand: left waiting when the index knows it,
 * else opened and, once admitted (or found shadowed), entered in the index. */
static bool load_indexed(rf_registry *reg, const char *path, GPtrArray *diags, GHashTable *index,
                         bool *dirty)
{
    struct stat st;
    const rf_index_entry *e = g_hash_table_lookup(index, path);
    bool current = stat(path, &st) == 0;
    if (e && current && rf_index_entry_matches(e, &st) && defer(reg, e))
        return true;
    guint before = reg->plugins->len;
    g_autofree char *shadow = NULL;
    bool ok = load_file_at(reg, path, diags, reg->seq++, &shadow);
    if (!ok || !current)
        return ok;
    const rf_plugin *p = NULL;
    for (guint i = 0; i < reg->plugins->len && reg->plugins->len > before; i++)
        if (strcmp(((rf_plugin *)g_ptr_array_index(reg->plugins, i))->path, path) == 0)
            p = g_ptr_array_index(reg->plugins, i);
    g_autoptr(GPtrArray) types = g_ptr_array_new();
    for (uint32_t i = 0; p && i < p->entry->node_count; i++)
        g_ptr_array_add(types, (gpointer)p->entry->nodes[i]->type);
    g_ptr_array_add(types, NULL);
    rf_index_entry *n =
        rf_index_entry_new(path, &st, p ? p->entry->id : shadow, (const char *const *)types->pdata);
    if (n && (p ? p->entry->node_count > 0 : shadow != NULL)) {
        g_hash_table_replace(index, n->path, n);
        *dirty = true;
    } else {
        rf_index_entry_free(n);
    }
    return ok;
}

/* A folder or file others may write to could plant code in this process: refuse it. */
static bool writable_by_others(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && (st.st_mode & S_IWOTH) != 0;
}

static gint compare_names(gconstpointer a, gconstpointer b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The *.so files of a folder, sorted so that loading order (and shadowing) is deterministic. */
static GPtrArray *list_modules(const char *dir)
{
    GPtrArray *files = g_ptr_array_new_with_free_func(g_free);
    GDir *d = g_dir_open(dir, 0, NULL);
    if (!d)
        return files;
    const char *name;
    while ((name = g_dir_read_name(d)))
        if (g_str_has_suffix(name, ".so"))
            g_ptr_array_add(files, g_build_filename(dir, name, NULL));
    g_dir_close(d);
    g_ptr_array_sort(files, compare_names);
    return files;
}

static int load_dir(rf_registry *reg, const char *dir, GPtrArray *diags, GHashTable *index,
                    bool *dirty)
{
    if (!g_file_test(dir, G_FILE_TEST_IS_DIR))
        return 0;
    if (writable_by_others(dir)) {
        rf_diags_add(diags, dir, 0, 0, NULL, NULL,
                     "plugin folder refused: it is writable by other users (chmod o-w it)");
        return 0;
    }
    g_autoptr(GPtrArray) files = list_modules(dir);
    /* In a libtool build tree the modules sit in .libs/ beside their .la files. */
    g_autofree char *libs = g_build_filename(dir, ".libs", NULL);
    if (files->len == 0 && g_file_test(libs, G_FILE_TEST_IS_DIR))
        return load_dir(reg, libs, diags, index, dirty);
    int loaded = 0;
    for (guint i = 0; i < files->len; i++) {
        const char *f = g_ptr_array_index(files, i);
        if (writable_by_others(f)) {
            rf_diags_add(diags, f, 0, 0, NULL, NULL,
                         "plugin refused: the file is writable by other users");
            continue;
        }
        loaded += index ? load_indexed(reg, f, diags, index, dirty)
                        : rf_registry_load_file(reg, f, diags);
    }
    return loaded;
}

int rf_registry_load_dir(rf_registry *reg, const char *dir, GPtrArray *diags)
{
    return load_dir(reg, dir, diags, NULL, NULL);
}

void rf_registry_load_search_path(rf_registry *reg, const char *const *extra, GPtrArray *diags)
{
    g_autofree char *file = reg->lazy ? rf_plugin_index_file() : NULL;
    GHashTable *index = file ? rf_plugin_index_read(file) : NULL;
    bool dirty = false;
    g_rec_mutex_lock(&reg->lock);
    for (const char *const *d = extra; d && *d; d++)
        load_dir(reg, *d, diags, index, &dirty);
    const char *env = g_getenv("RIGFLOW_PLUGIN_PATH");
    if (env && *env) {
        g_auto(GStrv) dirs = g_strsplit(env, ":", -1);
        for (char **d = dirs; *d; d++)
            if (**d)
                load_dir(reg, *d, diags, index, &dirty);
    }
    load_dir(reg, RF_PLUGINSDIR, diags, index, &dirty);
    g_rec_mutex_unlock(&reg->lock);
    if (dirty)
        rf_plugin_index_write(file, index);
    if (index)
        g_hash_table_destroy(index);
}

guint rf_registry_plugin_count(const rf_registry *reg)
{
    open_all(reg);
    return reg->plugins->len;
}

const rf_plugin *rf_registry_plugin(const rf_registry *reg, guint index)
{
    open_all(reg);
    return index < reg->plugins->len ? g_ptr_array_index(reg->plugins, index) : NULL;
}

const rf_plugin_entry *rf_plugin_entry_of(const rf_plugin *p)
{
    return p->entry;
}
const char *rf_plugin_path(const rf_plugin *p)
{
    return p->path;
}

const rf_node_desc *rf_registry_find(const rf_registry *creg, const char *type,
                                     const rf_plugin **plugin)
{
    rf_registry *reg = (rf_registry *)creg; /* loading adds answers, changes none given */
    g_rec_mutex_lock(&reg->lock);
    rf_plugin *p = g_hash_table_lookup(reg->types, type);
    rf_pending *waiting = p ? NULL : g_hash_table_lookup(reg->pending_types, type);
    if (waiting) {
        open_pending(reg, waiting);
        if (!(p = g_hash_table_lookup(reg->types, type))) { /* the file broke its index entry */
            open_all(reg);
            p = g_hash_table_lookup(reg->types, type);
        }
    }
    g_rec_mutex_unlock(&reg->lock);
    if (plugin)
        *plugin = p;
    if (!p)
        return NULL;
    for (uint32_t i = 0; i < p->entry->node_count; i++)
        if (strcmp(p->entry->nodes[i]->type, type) == 0)
            return p->entry->nodes[i];
    return NULL;
}

/* How well an importer's suffix list fits `path`: 2 it names the suffix, 1 it reads anything. */
static int suffix_fit(const char *suffixes, const char *path)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    const char *ext = dot && (!slash || dot > slash) ? dot + 1 : NULL;
    int fit = 0;
    g_auto(GStrv) list = g_strsplit(suffixes, "|", -1);
    for (char **s = list; *s; s++) {
        if (strcmp(*s, "*") == 0)
            fit = MAX(fit, 1);
        else if (ext && g_ascii_strcasecmp(*s, ext) == 0)
            fit = 2;
    }
    return fit;
}

const rf_node_desc *rf_registry_importer_for(const rf_registry *reg, const char *path,
                                             const char **path_param)
{
    const rf_node_desc *best = NULL;
    int best_fit = 0;
    open_all(reg);
    for (guint i = 0; i < reg->plugins->len; i++) {
        const rf_plugin_entry *e = ((rf_plugin *)g_ptr_array_index(reg->plugins, i))->entry;
        for (uint32_t k = 0; k < e->node_count; k++) {
            const rf_node_desc *d = e->nodes[k];
            const rf_importer_info *info = d->kind == RF_KIND_IMPORTER && d->get_extension
                                               ? d->get_extension(RF_IMPORTER_EXTENSION)
                                               : NULL;
            if (!info || info->size < RF_IMPORTER_INFO_SIZE_1_0 || !info->suffixes ||
                !info->path_param || rf_registry_find(reg, d->type, NULL) != d)
                continue; /* incomplete, or shadowed by an earlier folder on the path */
            int fit = suffix_fit(info->suffixes, path);
            if (fit > best_fit) {
                best = d, best_fit = fit;
                *path_param = info->path_param;
            }
        }
    }
    return best;
}

const char *rf_kind_name(rf_node_kind kind)
{
    static const char *const names[] = {"unknown", "importer", "exporter", "matcher", "retargeter",
                                        "ik",      "rigger",   "filter",   "report"};
    return kind >= RF_KIND_IMPORTER && kind <= RF_KIND_REPORT ? names[kind] : names[0];
}

const char *rf_param_type_name(rf_param_type type)
{
    static const char *const names[] = {"unknown", "bool", "int",        "float",
                                        "string",  "enum", "input path", "output path"};
    return type >= RF_PARAM_BOOL && type <= RF_PARAM_OUTPUT_PATH ? names[type] : names[0];
}
