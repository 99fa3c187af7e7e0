/* `rigflow plugin-check FILE.so...`: a plugin validator. Every check runs in a child process, so
 * a plugin that crashes or hangs is reported as a failure of that check instead of taking the
 * validator down. One line per check: PASS, WARN or FAIL, the file, the check, and why. Exit
 * status 0 when nothing failed, 1 when a check failed, 2 on a usage error. */
#include <dlfcn.h>
#include <elf.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "commands.h"

enum verdict { PASS = 0, WARN = 1, FAIL = 2 };

/* A check runs in a child: it prints its own lines to stdout and returns a verdict. */
typedef enum verdict (*check_fn)(const char *file);

static void report(enum verdict v, const char *file, const char *check, const char *fmt, ...)
    G_GNUC_PRINTF(4, 5);
static void report(enum verdict v, const char *file, const char *check, const char *fmt, ...)
{
    static const char *const names[] = {"PASS", "WARN", "FAIL"};
    va_list ap;
    va_start(ap, fmt);
    g_autofree char *msg = g_strdup_vprintf(fmt, ap);
    va_end(ap);
    printf("%s  %s  %s: %s\n", names[v], file, check, msg);
    fflush(stdout);
}

/* ---- loads ---- */

static enum verdict check_loads(const char *file)
{
    void *h = dlopen(file, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        report(FAIL, file, "loads", "%s", dlerror());
        return FAIL;
    }
    report(PASS, file, "loads", "opened with every symbol resolved");
    return PASS;
}

/* ---- exports ---- */

static bool linker_symbol(const char *name)
{
    static const char *const names[] = {"_init", "_fini", "_edata", "_end", "__bss_start"};
    for (size_t i = 0; i < G_N_ELEMENTS(names); i++)
        if (strcmp(name, names[i]) == 0)
            return true;
    return false;
}

/* Names of the defined, default-visibility dynamic symbols of a 64-bit ELF image other than the
 * entry, into `extra`. Returns false when the image is not one we can read. Every offset is
 * bounds-checked: the file may be hostile. */
static bool elf_extra_exports(const unsigned char *img, size_t len, GString *extra)
{
    if (len < sizeof(Elf64_Ehdr) || memcmp(img, ELFMAG, SELFMAG) != 0 ||
        img[EI_CLASS] != ELFCLASS64)
        return false;
    const Elf64_Ehdr *eh = (const Elf64_Ehdr *)img;
    if (eh->e_shentsize != sizeof(Elf64_Shdr) || eh->e_shoff > len ||
        (size_t)eh->e_shnum * sizeof(Elf64_Shdr) > len - eh->e_shoff)
        return false;
    const Elf64_Shdr *sh = (const Elf64_Shdr *)(img + eh->e_shoff);
    for (unsigned i = 0; i < eh->e_shnum; i++) {
        if (sh[i].sh_type != SHT_DYNSYM || sh[i].sh_link >= eh->e_shnum)
            continue;
        const Elf64_Shdr *str = &sh[sh[i].sh_link];
        if (sh[i].sh_offset > len || sh[i].sh_size > len - sh[i].sh_offset ||
            str->sh_offset > len || str->sh_size > len - str->sh_offset)
            return false;
        const Elf64_Sym *sym = (const Elf64_Sym *)(img + sh[i].sh_offset);
        size_t n = sh[i].sh_size / sizeof(Elf64_Sym);
        for (size_t k = 0; k < n; k++) {
            unsigned bind = ELF64_ST_BIND(sym[k].st_info);
            if (sym[k].st_shndx == SHN_UNDEF || sym[k].st_name >= str->sh_size ||
                (bind != STB_GLOBAL && bind != STB_WEAK) ||
                ELF64_ST_VISIBILITY(sym[k].st_other) != STV_DEFAULT)
                continue;
            const char *name = (const char *)img + str->sh_offset + sym[k].st_name;
            if (!memchr(name, '\0', str->sh_size - sym[k].st_name) || !*name ||
                strcmp(name, RF_PLUGIN_ENTRY_SYMBOL) == 0 || linker_symbol(name))
                continue;
            g_string_append_printf(extra, "%s%s", extra->len ? ", " : "", name);
        }
    }
    return true;
}

static enum verdict check_exports(const char *file)
{
    g_autofree char *img = NULL;
    gsize len = 0;
    if (!g_file_get_contents(file, &img, &len, NULL)) {
        report(FAIL, file, "exports", "cannot read the file");
        return FAIL;
    }
    g_autoptr(GString) extra = g_string_new(NULL);
    if (!elf_extra_exports((const unsigned char *)img, len, extra)) {
        report(WARN, file, "exports", "not a 64-bit ELF file: exports not inspected");
        return WARN;
    }
    if (extra->len) {
        report(FAIL, file, "exports", "exports more than %s: %s (build with -fvisibility=hidden)",
               RF_PLUGIN_ENTRY_SYMBOL, extra->str);
        return FAIL;
    }
    report(PASS, file, "exports", "only %s", RF_PLUGIN_ENTRY_SYMBOL);
    return PASS;
}

/* ---- entry (ABI, descriptors, init) through the host's own loader ---- */

static rf_registry *load_alone(const char *file, enum verdict *v)
{
    rf_registry *reg = rf_registry_new();
    g_autoptr(GPtrArray) diags = rf_diags_new();
    if (rf_registry_load_file(reg, file, diags) && rf_registry_plugin_count(reg) == 1) {
        *v = PASS;
        return reg;
    }
    for (guint i = 0; i < diags->len; i++) {
        rf_diag *d = g_ptr_array_index(diags, i);
        report(FAIL, file, "entry", "%s", d->message);
    }
    *v = FAIL;
    rf_registry_free(reg);
    return NULL;
}

static enum verdict check_entry(const char *file)
{
    enum verdict v;
    rf_registry *reg = load_alone(file, &v);
    if (reg) {
        const rf_plugin_entry *e = rf_plugin_entry_of(rf_registry_plugin(reg, 0));
        report(PASS, file, "entry", "%s %s, ABI %u.%u.%u, %u node type%s, init passed", e->id,
               e->version ? e->version : "", e->abi.major, e->abi.minor, e->abi.patch,
               e->node_count, e->node_count == 1 ? "" : "s");
        rf_registry_free(reg);
    }
    return v;
}

/* ---- descriptors ---- */

static bool id_ok(const char *id)
{
    if (!*id || !g_ascii_islower(*id))
        return false;
    for (const char *c = id; *c; c++)
        if (!g_ascii_islower(*c) && !g_ascii_isdigit(*c) && *c != '.' && *c != '-' && *c != '_')
            return false;
    return true;
}

static bool port_type_known(const char *type)
{
    static const char *const known[] = {RF_TYPE_SKELETON, RF_TYPE_ANIMATION, RF_TYPE_MESH,
                                        RF_TYPE_MAPPING,  "rigflow.clips",   "rigflow.ik-solver"};
    for (size_t i = 0; i < G_N_ELEMENTS(known); i++)
        if (strcmp(type, known[i]) == 0)
            return true;
    /* a third party's own type: reverse-DNS (two dots at least), outside the rigflow namespace */
    const char *dot = strchr(type, '.');
    return !g_str_has_prefix(type, "rigflow.") && dot && strchr(dot + 1, '.');
}

static enum verdict worst(enum verdict a, enum verdict b)
{
    return a > b ? a : b;
}

static enum verdict check_ports(const char *file, const rf_node_desc *d, const rf_port_desc *ports,
                                uint32_t count)
{
    enum verdict v = PASS;
    for (uint32_t i = 0; i < count; i++) {
        for (uint32_t k = 0; k < i; k++)
            if (strcmp(ports[i].name, ports[k].name) == 0) {
                report(FAIL, file, "descriptors", "%s: port '%s' declared twice", d->type,
                       ports[i].name);
                v = FAIL;
            }
        if (!port_type_known(ports[i].type)) {
            report(WARN, file, "descriptors",
                   "%s: port '%s' has type '%s', neither a rigflow type nor a reverse-DNS id",
                   d->type, ports[i].name, ports[i].type);
            v = worst(v, WARN);
        }
        if (!ports[i].doc || !*ports[i].doc) {
            report(WARN, file, "descriptors", "%s: port '%s' has no doc", d->type, ports[i].name);
            v = worst(v, WARN);
        }
    }
    return v;
}

static enum verdict check_param(const char *file, const rf_node_desc *d, const rf_param_desc *p)
{
    enum verdict v = PASS;
    bool numeric = p->type == RF_PARAM_INT || p->type == RF_PARAM_FLOAT;
    if (numeric && (p->flags & RF_PARAM_HAS_RANGE) && !(p->flags & RF_PARAM_REQUIRED) &&
        (p->default_number < p->min || p->default_number > p->max || p->min > p->max)) {
        report(FAIL, file, "descriptors", "%s: parameter '%s' default %g is outside [%g, %g]",
               d->type, p->name, p->default_number, p->min, p->max);
        v = FAIL;
    }
    if (p->type == RF_PARAM_ENUM && !(p->flags & RF_PARAM_REQUIRED)) {
        g_auto(GStrv) choices = g_strsplit(p->choices, "|", -1);
        const char *def = p->default_string ? p->default_string : "";
        if (!g_strv_contains((const char *const *)choices, def)) {
            report(FAIL, file, "descriptors", "%s: parameter '%s' default \"%s\" is not one of %s",
                   d->type, p->name, def, p->choices);
            v = FAIL;
        }
    }
    if (!p->doc || !*p->doc) {
        report(WARN, file, "descriptors", "%s: parameter '%s' has no doc", d->type, p->name);
        v = worst(v, WARN);
    }
    return v;
}

static enum verdict check_node_desc(const char *file, const rf_node_desc *d)
{
    enum verdict v = PASS;
    if (!id_ok(d->type)) {
        report(FAIL, file, "descriptors",
               "node type id '%s': expected lower-case letters, digits, '.', '-', '_'", d->type);
        v = FAIL;
    }
    if (d->kind < RF_KIND_IMPORTER || d->kind > RF_KIND_REPORT) {
        report(FAIL, file, "descriptors", "%s: unknown kind %d", d->type, (int)d->kind);
        v = FAIL;
    }
    if (!d->doc || !*d->doc) {
        report(WARN, file, "descriptors", "%s: no doc", d->type);
        v = worst(v, WARN);
    }
    v = worst(v, check_ports(file, d, d->inputs, d->input_count));
    v = worst(v, check_ports(file, d, d->outputs, d->output_count));
    for (uint32_t i = 0; i < d->param_count; i++)
        v = worst(v, check_param(file, d, &d->params[i]));
    return v;
}

/* Loads the plugin alone and applies `fn` to each of its node types; the worst verdict. */
typedef enum verdict (*node_check_fn)(const char *file, rf_registry *reg, const rf_node_desc *d);
static enum verdict for_each_node(const char *file, node_check_fn fn)
{
    enum verdict v;
    rf_registry *reg = load_alone(file, &v);
    if (!reg)
        return v;
    const rf_plugin_entry *e = rf_plugin_entry_of(rf_registry_plugin(reg, 0));
    for (uint32_t i = 0; i < e->node_count; i++)
        v = worst(v, fn(file, reg, e->nodes[i]));
    rf_registry_free(reg);
    return v;
}

static enum verdict describe_one(const char *file, rf_registry *reg, const rf_node_desc *d)
{
    (void)reg;
    return check_node_desc(file, d);
}

static enum verdict check_descriptors(const char *file)
{
    enum verdict v = for_each_node(file, describe_one);
    if (v == PASS)
        report(PASS, file, "descriptors", "ids, kinds, port types, defaults and docs");
    return v;
}

/* ---- create and destroy each node type with default parameters ---- */

static const rf_param_desc *required_param(const rf_node_desc *d)
{
    for (uint32_t i = 0; i < d->param_count; i++)
        if (d->params[i].flags & RF_PARAM_REQUIRED)
            return &d->params[i];
    return NULL;
}

static enum verdict create_one(const char *file, rf_registry *reg, const rf_node_desc *d)
{
    const rf_param_desc *req = required_param(d);
    g_autoptr(GPtrArray) diags = rf_diags_new();
    if (req) {
        report(PASS, file, "create", "%s: not created (parameter '%s' has no default)", d->type,
               req->name);
        return PASS;
    }
    if (rf_node_type_try_create(reg, d->type, diags)) {
        report(PASS, file, "create", "%s: created and destroyed with defaults", d->type);
        return PASS;
    }
    g_autofree char *why =
        diags->len ? rf_diag_format(g_ptr_array_index(diags, 0)) : g_strdup("create failed");
    report(FAIL, file, "create", "%s: %s", d->type, why);
    return FAIL;
}

static enum verdict check_create(const char *file)
{
    return for_each_node(file, create_one);
}

/* ---- self-tests the node types declare ---- */

static enum verdict selftest_one(const char *file, rf_registry *reg, const rf_node_desc *d)
{
    (void)reg;
    const rf_selftest *t = d->get_extension ? d->get_extension(RF_SELFTEST_EXTENSION) : NULL;
    if (!t || t->size < RF_SELFTEST_SIZE_1_0 || !t->run) {
        report(PASS, file, "selftest", "%s: declares no self-test", d->type);
        return PASS;
    }
    char err[512] = "";
    if (t->run(rf_host_table(), err, sizeof err)) {
        report(PASS, file, "selftest", "%s: passed", d->type);
        return PASS;
    }
    err[sizeof err - 1] = '\0';
    report(FAIL, file, "selftest", "%s: %s", d->type, err[0] ? err : "failed");
    return FAIL;
}

static enum verdict check_selftest(const char *file)
{
    return for_each_node(file, selftest_one);
}

/* ---- running checks in child processes ---- */

/* A check's child exits with CHECK_EXIT_BASE + its verdict. Any other status means plugin code
 * ended the process: exit() called by the plugin, or a crash caught by a sanitizer, which exits
 * with status 1 instead of dying by the signal. Neither may pass for a verdict. */
#define CHECK_EXIT_BASE 64

static enum verdict run_isolated(check_fn fn, const char *file, const char *name)
{
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        alarm(30); /* a hung plugin fails its check instead of hanging the validator */
        _exit(CHECK_EXIT_BASE + (int)fn(file));
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0) {
        report(FAIL, file, name, "could not start the check process");
        return FAIL;
    }
    if (WIFSIGNALED(status)) {
        report(FAIL, file, name, "the plugin crashed the check (%s)", strsignal(WTERMSIG(status)));
        return FAIL;
    }
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code >= CHECK_EXIT_BASE && code <= CHECK_EXIT_BASE + FAIL)
        return (enum verdict)(code - CHECK_EXIT_BASE);
    report(FAIL, file, name, "the plugin crashed the check (it ended the process, exit status %d)",
           code);
    return FAIL;
}

int rf_cmd_plugin_check(rf_registry *reg, int argc, char **argv)
{
    (void)reg; /* each check loads the file alone, in its own process */
    if (!rf_parse_options("plugin-check", "FILE.so...",
                          "Check plugins: loading, exports, ABI, descriptors, create/destroy, "
                          "self-tests.\nEach check runs in its own process.",
                          NULL, &argc, &argv))
        return RF_EXIT_USAGE;
    if (argc < 2) {
        fprintf(stderr, "rigflow plugin-check: expected one or more plugin files\n");
        return RF_EXIT_USAGE;
    }
    static const struct {
        const char *name;
        check_fn fn;
    } checks[] = {{"loads", check_loads},   {"exports", check_exports},
                  {"entry", check_entry},   {"descriptors", check_descriptors},
                  {"create", check_create}, {"selftest", check_selftest}};
    enum verdict all = PASS;
    for (int f = 1; f < argc; f++)
        for (size_t i = 0; i < G_N_ELEMENTS(checks); i++) {
            enum verdict v = run_isolated(checks[i].fn, argv[f], checks[i].name);
            all = worst(all, v);
            if (v == FAIL && (checks[i].fn == check_loads || checks[i].fn == check_entry))
                break; /* the later checks need the plugin loaded */
        }
    return all == FAIL ? RF_EXIT_RUN : RF_EXIT_OK;
}
