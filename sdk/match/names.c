/* Name normalisation and name-based joint mapping (see names.h). */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rigflow/match-names.h"

#define RF_MAX_TOKENS 16
#define RF_TOKEN_SIZE 32

typedef struct rf_tokens {
    char t[RF_MAX_TOKENS][RF_TOKEN_SIZE];
    int n;
} rf_tokens;

static void push(rf_tokens *tk, const char *s, size_t len)
{
    if (len == 0 || tk->n == RF_MAX_TOKENS)
        return;
    if (len >= RF_TOKEN_SIZE)
        len = RF_TOKEN_SIZE - 1;
    for (size_t i = 0; i < len; i++)
        tk->t[tk->n][i] = (char)tolower((unsigned char)s[i]);
    tk->t[tk->n++][len] = '\0';
}

/* A word boundary before s[i]: letters to digits and back, lower to upper ("upLeg"), and the last
 * capital of a run before a lower-case letter ("LHip" is L, Hip). */
static bool boundary(const char *s, size_t i)
{
    unsigned char a = (unsigned char)s[i - 1], b = (unsigned char)s[i];
    if (isdigit(a) != isdigit(b))
        return true;
    if (islower(a) && isupper(b))
        return true;
    return isupper(a) && isupper(b) && islower((unsigned char)s[i + 1]);
}

static void tokenize(const char *name, rf_tokens *tk)
{
    const char *s = name;
    for (const char *p = name; *p; p++) /* namespaces: mixamorig:Hips, Root|Hips */
        if (*p == ':' || *p == '|')
            s = p + 1;
    size_t start = 0, i = 0;
    tk->n = 0;
    for (; s[i]; i++) {
        if (!isalnum((unsigned char)s[i])) {
            push(tk, s + start, i - start);
            start = i + 1;
        } else if (i > start && boundary(s, i)) {
            push(tk, s + start, i - start);
            start = i;
        }
    }
    push(tk, s + start, i - start);
}

static bool in_list(const char *w, const char *const *list)
{
    for (; *list; list++)
        if (strcmp(w, *list) == 0)
            return true;
    return false;
}

static bool is_number(const char *w)
{
    return *w && strspn(w, "0123456789") == strlen(w);
}

/* Side tokens, also glued at the front of a lower-case word ("leftarm"). */
static int take_side(rf_tokens *tk)
{
    static const char *const left[] = {"l", "left", "lf", "lft", NULL};
    static const char *const right[] = {"r", "right", "rt", "rgt", NULL};
    int side = 0;
    for (int i = 0; i < tk->n; i++) {
        char *w = tk->t[i];
        int s = in_list(w, left) ? 1 : in_list(w, right) ? 2 : 0;
        if (!s && strncmp(w, "left", 4) == 0 && w[4])
            memmove(w, w + 4, strlen(w + 4) + 1), side = 1;
        else if (!s && strncmp(w, "right", 5) == 0 && w[5])
            memmove(w, w + 5, strlen(w + 5) + 1), side = 2;
        if (s) {
            side = s;
            memmove(&tk->t[i], &tk->t[i + 1], (size_t)(tk->n - i - 1) * RF_TOKEN_SIZE);
            tk->n--, i--;
        }
    }
    return side;
}

/* Rig and exporter prefixes that say nothing about the joint, dropped while something is left. */
static void drop_prefixes(rf_tokens *tk)
{
    static const char *const stop[] = {"mixamorig", "bip", "b",    "def",       "org",        "mch",
                                       "jnt",       "j",   "bn",   "bone",      "sk",         "cc",
                                       "armature",  "rig", "char", "character", "valvebiped", NULL};
    while (tk->n > 1 && (in_list(tk->t[0], stop) || (is_number(tk->t[0]) && tk->n > 1))) {
        memmove(&tk->t[0], &tk->t[1], (size_t)(tk->n - 1) * RF_TOKEN_SIZE);
        tk->n--;
    }
}

/* Two-word names that mean one thing. */
static void join_pairs(rf_tokens *tk)
{
    static const char *const pairs[][3] = {
        {"up", "leg", "thigh"},       {"upper", "leg", "thigh"},  {"lower", "leg", "shin"},
        {"upper", "arm", "upperarm"}, {"up", "arm", "upperarm"},  {"lower", "arm", "forearm"},
        {"fore", "arm", "forearm"},   {"toe", "base", "toe"},     {"lower", "back", "spine"},
        {"upper", "chest", "chest"},  {"finger", "base", "hand"}, {"hip", "joint", "hipjoint"},
    };
    for (int i = 0; i + 1 < tk->n; i++)
        for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; p++)
            if (strcmp(tk->t[i], pairs[p][0]) == 0 && strcmp(tk->t[i + 1], pairs[p][1]) == 0) {
                snprintf(tk->t[i], RF_TOKEN_SIZE, "%s", pairs[p][2]);
                memmove(&tk->t[i + 1], &tk->t[i + 2], (size_t)(tk->n - i - 2) * RF_TOKEN_SIZE);
                tk->n--;
                break;
            }
}

/* Synonyms to one concept word; "hip" and "leg" and "arm" read differently with a side. */
static const char *concept(const char *w, int side)
{
    static const char *const table[][2] = {
        {"hips", "pelvis"},       {"pelvis", "pelvis"},
        {"upleg", "thigh"},       {"thigh", "thigh"},
        {"femur", "thigh"},       {"shin", "shin"},
        {"calf", "shin"},         {"knee", "shin"},
        {"crus", "shin"},         {"lowerleg", "shin"},
        {"upperleg", "thigh"},    {"ankle", "foot"},
        {"foot", "foot"},         {"toes", "toe"},
        {"toe", "toe"},           {"ball", "toe"},
        {"back", "spine"},        {"abdomen", "spine"},
        {"ab", "spine"},          {"torso", "spine"},
        {"waist", "spine"},       {"spine", "spine"},
        {"chest", "chest"},       {"thorax", "chest"},
        {"ribcage", "chest"},     {"neck", "neck"},
        {"head", "head"},         {"skull", "head"},
        {"clavicle", "clavicle"}, {"collar", "clavicle"},
        {"clav", "clavicle"},     {"collarbone", "clavicle"},
        {"humerus", "upperarm"},  {"upperarm", "upperarm"},
        {"forearm", "forearm"},   {"lowerarm", "forearm"},
        {"elbow", "forearm"},     {"ulna", "forearm"},
        {"radius", "forearm"},    {"hand", "hand"},
        {"wrist", "hand"},        {"palm", "hand"},
        {"fist", "hand"},         {"thumb", "thumb"},
        {"index", "index"},       {"pointer", "index"},
        {"middle", "middle"},     {"ring", "ring"},
        {"pinky", "pinky"},       {"little", "pinky"},
        {"fingers", "finger"},    {"finger", "finger"},
        {"jaw", "jaw"},           {"eye", "eye"},
        {"ear", "ear"},           {"tail", "tail"},
        {"shoulder", "shoulder"},
    };
    if (strcmp(w, "hip") == 0)
        return side ? "thigh" : "pelvis";
    if (strcmp(w, "leg") == 0)
        return side ? "shin" : "leg";
    if (strcmp(w, "arm") == 0)
        return side ? "upperarm" : "arm";
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (strcmp(w, table[i][0]) == 0)
            return table[i][1];
    return w;
}

void rf_name_normalize(const char *name, bool drop_index, rf_name_key *out)
{
    rf_tokens tk;
    tokenize(name ? name : "", &tk);
    out->side = take_side(&tk);
    drop_prefixes(&tk);
    if (drop_index && tk.n > 1 && is_number(tk.t[tk.n - 1]))
        tk.n--;
    join_pairs(&tk);
    out->words[0] = '\0';
    size_t used = 0;
    for (int i = 0; i < tk.n; i++) {
        const char *w = is_number(tk.t[i]) ? tk.t[i] : concept(tk.t[i], out->side);
        if (is_number(w)) /* "01" and "1" are the same ordinal */
            while (w[0] == '0' && w[1])
                w++;
        int n = snprintf(out->words + used, sizeof out->words - used, "%s%s", i ? " " : "", w);
        if (n < 0 || (size_t)n >= sizeof out->words - used)
            break;
        used += (size_t)n;
    }
}

/* Words that are near each other: a shoulder is named for the clavicle in some rigs and for the
 * upper arm in others. */
static double related(const char *a, const char *b)
{
    static const char *const near[][2] = {
        {"shoulder", "clavicle"}, {"shoulder", "upperarm"}, {"chest", "spine"},
        {"finger", "index"},      {"finger", "middle"},     {"finger", "ring"},
        {"finger", "pinky"},      {"hipjoint", "pelvis"},   {"hipjoint", "thigh"},
        {"leg", "thigh"},         {"arm", "upperarm"},
    };
    if (strcmp(a, b) == 0)
        return 1;
    for (size_t i = 0; i < sizeof near / sizeof near[0]; i++)
        if ((strcmp(a, near[i][0]) == 0 && strcmp(b, near[i][1]) == 0) ||
            (strcmp(b, near[i][0]) == 0 && strcmp(a, near[i][1]) == 0))
            return 0.7;
    if (is_number(a) && is_number(b))
        return 0.5; /* another ordinal of the same thing */
    return 0;
}

static int split_words(const char *words, char out[][RF_TOKEN_SIZE], int max)
{
    int n = 0;
    const char *p = words;
    while (*p && n < max) {
        size_t len = strcspn(p, " ");
        snprintf(out[n++], RF_TOKEN_SIZE, "%.*s", (int)(len < RF_TOKEN_SIZE ? len : 31), p);
        p += len;
        while (*p == ' ')
            p++;
    }
    return n;
}

double rf_name_similarity(const rf_name_key *a, const rf_name_key *b)
{
    if (a->side != b->side)
        return 0;
    char wa[RF_MAX_TOKENS][RF_TOKEN_SIZE], wb[RF_MAX_TOKENS][RF_TOKEN_SIZE];
    int na = split_words(a->words, wa, RF_MAX_TOKENS),
        nb = split_words(b->words, wb, RF_MAX_TOKENS);
    if (na == 0 || nb == 0)
        return 0;
    bool used[RF_MAX_TOKENS] = {false};
    double sum = 0;
    for (int i = 0; i < na; i++) { /* greedy: each word of a takes its best partner in b */
        int best = -1;
        double bs = 0;
        for (int k = 0; k < nb; k++) {
            double r = used[k] ? 0 : related(wa[i], wb[k]);
            if (r > bs)
                bs = r, best = k;
        }
        if (best >= 0)
            used[best] = true, sum += bs;
    }
    return sum / (na > nb ? na : nb);
}

/* A running index: every name of the skeleton ends in a number, all different. */
static bool has_running_index(const rf_skeleton *s)
{
    if (s->joint_count < 3)
        return false;
    long *seen = malloc(s->joint_count * sizeof *seen);
    if (!seen)
        return false;
    bool all = true;
    for (uint32_t j = 0; j < s->joint_count && all; j++) {
        const char *n = s->joints[j].name ? s->joints[j].name : "";
        size_t len = strlen(n), k = len;
        while (k > 0 && isdigit((unsigned char)n[k - 1]))
            k--;
        all = k < len && k > 0 && !isdigit((unsigned char)n[k - 1]);
        seen[j] = all ? strtol(n + k, NULL, 10) : 0;
        for (uint32_t q = 0; all && q < j; q++)
            all = seen[q] != seen[j];
    }
    free(seen);
    return all;
}

static rf_name_key *keys_of(const rf_skeleton *s)
{
    rf_name_key *k = calloc(s->joint_count ? s->joint_count : 1, sizeof *k);
    bool drop = has_running_index(s);
    for (uint32_t j = 0; k && j < s->joint_count; j++)
        rf_name_normalize(s->joints[j].name, drop, &k[j]);
    return k;
}

static bool set_entry(rf_map_entry *e, uint32_t source, uint32_t joint, double score)
{
    e->metrics = calloc(1, sizeof *e->metrics);
    if (!e->metrics)
        return false;
    e->metrics[0] = score;
    if (source == UINT32_MAX)
        return true;
    e->inputs = calloc(1, sizeof *e->inputs);
    if (!e->inputs)
        return false;
    e->input_count = 1;
    e->inputs[0] = (rf_map_input){source, joint, 1.0f, 0.0f, 0};
    e->score = score;
    return true;
}

static bool match_joint(const rf_name_key *tk, rf_name_key *const *sk,
                        const rf_skeleton *const *sources, uint32_t n, double min_score,
                        rf_map_entry *e)
{
    uint32_t bs = UINT32_MAX, bj = 0;
    double best = 0;
    for (uint32_t k = 0; k < n; k++)
        for (uint32_t j = 0; j < sources[k]->joint_count; j++) {
            double s = rf_name_similarity(tk, &sk[k][j]);
            if (s > best)
                best = s, bs = k, bj = j;
        }
    if (best < min_score)
        bs = UINT32_MAX;
    return set_entry(e, bs, bj, 100.0 * best);
}

rf_mapping *rf_names_match(const rf_skeleton *target, const rf_skeleton *const *sources,
                           uint32_t source_count, double min_score, char *err, size_t err_size)
{
    if (!target || source_count == 0) {
        snprintf(err, err_size, "no %s", target ? "source skeleton to map from" : "target");
        return NULL;
    }
    rf_mapping *m = rf_mapping_new(target->joint_count, source_count);
    rf_name_key *tk = keys_of(target);
    rf_name_key **sk = calloc(source_count, sizeof *sk);
    bool ok = m && tk && sk;
    for (uint32_t k = 0; ok && k < source_count; k++)
        ok = (sk[k] = keys_of(sources[k])) != NULL;
    if (ok) {
        m->metric_count = 1;
        m->metric_names = calloc(1, sizeof *m->metric_names);
        ok = m->metric_names && (m->metric_names[0] = malloc(5)) != NULL;
        if (ok)
            memcpy(m->metric_names[0], "name", 5);
    }
    double floor = min_score > 0 ? min_score : 0.5;
    for (uint32_t j = 0; ok && j < target->joint_count; j++)
        ok = match_joint(&tk[j], sk, sources, source_count, floor, &m->entries[j]);
    for (uint32_t k = 0; sk && k < source_count; k++)
        free(sk[k]);
    free(sk);
    free(tk);
    if (!ok) {
        rf_mapping_free(m);
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    return m;
}
