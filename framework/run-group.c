/* Nodes that process at once. Consecutive nodes of the run's order whose types are marked
 * RF_NODE_CONCURRENT and that do not read each other's outputs form a group (in the retarget
 * pipeline: the two imports and the IK solver; the export, the summary and the measures). The
 * run's thread processes the group's first node as a lone node would, printing straight to the
 * standard streams; worker threads take the others in order, each printing into a buffer of its
 * own (rf_held). Once all have returned, the run's thread reports them in order, each buffer
 * copied out as it stands, so stdout and stderr read byte for byte as a run of one node at a
 * time; the first node that failed ends the report, and what the nodes after it printed or
 * wrote is dropped, as if they had never run (their temporary files go with the failed run). */
#include <stdio.h>
#include <stdlib.h>

#include "pipeline-internal.h"

/* ---- what a node prints while it runs beside others ---- */

typedef struct rf_held_line {
    size_t at;  /* bytes of stdout the node had printed when it logged the line */
    char *text; /* the whole line, for stderr */
} rf_held_line;

struct rf_held {
    FILE *out; /* open_memstream over buf/len */
    char *buf;
    size_t len;
    GMutex lock;  /* a node's own threads may log at once */
    GArray *logs; /* rf_held_line */
};

static rf_held *held_new(void)
{
    rf_held *h = g_new0(rf_held, 1);
    h->out = open_memstream(&h->buf, &h->len);
    if (!h->out) {
        g_free(h);
        return NULL;
    }
    g_mutex_init(&h->lock);
    h->logs = g_array_new(FALSE, FALSE, sizeof(rf_held_line));
    return h;
}

static void held_free(rf_held *h)
{
    if (!h)
        return;
    fclose(h->out);
    free(h->buf);
    for (guint i = 0; i < h->logs->len; i++)
        g_free(g_array_index(h->logs, rf_held_line, i).text);
    g_array_free(h->logs, TRUE);
    g_mutex_clear(&h->lock);
    g_free(h);
}

FILE *rf_held_out(rf_held *h)
{
    return h->out;
}

void rf_held_log(rf_held *h, const char *line)
{
    g_mutex_lock(&h->lock);
    fflush(h->out); /* len counts what was printed before the line */
    rf_held_line l = {h->len, g_strdup(line)};
    g_array_append_val(h->logs, l);
    g_mutex_unlock(&h->lock);
}

/* Copies a finished node's stdout and log lines out, interleaved as they were printed, through
 * the same stdio streams a lone node writes to (so their buffering is the same too). */
static void held_flush(rf_held *h, FILE *out)
{
    fflush(h->out);
    size_t at = 0;
    for (guint i = 0; i < h->logs->len; i++) {
        const rf_held_line *l = &g_array_index(h->logs, rf_held_line, i);
        fwrite(h->buf + at, 1, l->at - at, out);
        fputs(l->text, stderr);
        at = l->at;
    }
    fwrite(h->buf + at, 1, h->len - at, out);
}

/* ---- the group ---- */

/* Whether node n reads an output of a node at order positions [first, end). Within consecutive
 * positions of a topological order a direct edge is enough: any path between two of them runs
 * through positions between them. */
static bool reads_from(rf_pipeline *p, const rf_node *n, guint first, guint end)
{
    for (uint32_t k = 0; k < n->desc->input_count; k++)
        for (guint e = 0; e < n->inputs[k]->len; e++) {
            const rf_node *src = ((rf_conn *)g_ptr_array_index(n->inputs[k], e))->src;
            for (guint g = first; g < end; g++)
                if (rf_run_node_at(p, g) == src)
                    return true;
        }
    return false;
}

/* The position after the group that starts at `first`: a lone node's next position unless
 * several may process at once. */
static guint group_end(rf_pipeline *p, guint first, guint jobs)
{
    guint end = first + 1;
    if (jobs < 2 || !(rf_run_node_at(p, first)->desc->flags & RF_NODE_CONCURRENT))
        return end;
    while (end < p->order->len) {
        rf_node *n = rf_run_node_at(p, end);
        if (!(n->desc->flags & RF_NODE_CONCURRENT) || reads_from(p, n, first, end))
            break;
        end++;
    }
    return end;
}

typedef struct rf_group {
    rf_pipeline *p;
    gint next; /* the next order position to take (atomic) */
    guint end;
} rf_group;

static bool cancelled(const rf_pipeline *p)
{
    return p->opts->cancel_flag && *p->opts->cancel_flag;
}

/* Takes the group's nodes one by one until none is left; an interrupted run leaves the rest
 * unprocessed (rf_node_report says so for the first of them). */
static gpointer group_worker(gpointer data)
{
    rf_group *g = data;
    for (guint i; (i = (guint)g_atomic_int_add(&g->next, 1)) < g->end;)
        if (!cancelled(g->p))
            rf_node_process(rf_run_node_at(g->p, i));
    return NULL;
}

static void drop_held(rf_pipeline *p, guint first, guint end)
{
    for (guint i = first; i < end; i++) {
        rf_node *n = rf_run_node_at(p, i);
        g_clear_pointer(&n->held, held_free);
    }
}

/* Gives every node of the group but the first a buffer; false (none given) when one cannot be
 * made, and the group then processes one node at a time. */
static bool hold_all(rf_pipeline *p, guint first, guint end)
{
    for (guint i = first + 1; i < end; i++)
        if (!(rf_run_node_at(p, i)->held = held_new())) {
            drop_held(p, first, end);
            return false;
        }
    return true;
}

/* Reports the held nodes in order, each after its output is copied out. */
static bool report_held(rf_pipeline *p, guint first, guint end, GPtrArray *diags)
{
    for (guint i = first + 1; i < end; i++) {
        rf_node *n = rf_run_node_at(p, i);
        if (n->held)
            held_flush(n->held, p->opts->out ? p->opts->out : stdout);
        g_clear_pointer(&n->held, held_free);
        if (!rf_node_report(n, diags))
            return false;
    }
    return true;
}

/* The nodes at [first, end) one after another, as every run did before groups. */
static bool run_one_by_one(rf_pipeline *p, guint first, guint end, GPtrArray *diags)
{
    for (guint i = first; i < end; i++) {
        rf_node *n = rf_run_node_at(p, i);
        if (i > first && cancelled(p))
            return rf_node_report(n, diags); /* says the node did not run */
        rf_node_process(n);
        if (!rf_node_report(n, diags))
            return false;
    }
    return true;
}

/* Starts up to `count` worker threads (at most 64) on the group; returns how many started. */
static guint start_workers(rf_group *g, guint count, GThread **threads)
{
    guint started = 0;
    for (; started < MIN(count, 64u); started++)
        if (!(threads[started] = g_thread_try_new("rf-node", group_worker, g, NULL)))
            break; /* fewer threads: the run's own takes what is left */
    return started;
}

bool rf_run_group(rf_pipeline *p, guint first, guint jobs, guint *next, GPtrArray *diags)
{
    guint end = group_end(p, first, jobs);
    *next = end;
    if (end - first < 2 || !hold_all(p, first, end))
        return run_one_by_one(p, first, end, diags);
    gint64 t0 = g_get_monotonic_time();
    rf_node *head = rf_run_node_at(p, first);
    rf_group g = {p, (gint)first + 1, end};
    GThread *threads[64];
    guint started = start_workers(&g, MIN(jobs, end - first) - 1, threads);
    rf_node_process(head);
    bool ok = rf_node_report(head, diags); /* its fsync begins while the others still run */
    if (!ok) /* the run ends here: what has not started yet will not */
        g_atomic_int_set(&g.next, (gint)end);
    group_worker(&g);
    for (guint t = 0; t < started; t++)
        g_thread_join(threads[t]);
    if (ok && p->opts->profile) /* before the nodes' own lines: it is a part of the run */
        fprintf(stderr, "profile: nodes %s to %s at once (%u threads): %.3f ms\n", head->id,
                rf_run_node_at(p, end - 1)->id, started + 1,
                (double)(g_get_monotonic_time() - t0) / 1000.0);
    ok = ok && report_held(p, first, end, diags);
    drop_held(p, first, end);
    return ok;
}
