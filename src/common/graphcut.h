/* graphcut: s-t minimum cut / maximum flow by the Boykov-Kolmogorov
 * algorithm (Boykov & Kolmogorov, "An experimental comparison of
 * min-cut/max-flow algorithms for energy minimization in vision", PAMI
 * 2004), for the seams of graph-cut textures (Kwatra et al. 2003) on grid
 * graphs of up to millions of nodes.
 *
 * Two search trees grow from the source S and the sink T through
 * non-saturated arcs; when they touch, flow is pushed along the path found
 * (augmentation), which cuts saturated arcs out of the trees; the orphaned
 * nodes then look for a new parent in their own tree (adoption) or become
 * free. On grids this is much faster than shortest-path methods because the
 * trees are reused instead of rebuilt after every augmentation.
 *
 *     pw_graph g;  double flow;  pw_err e;
 *     pw_err_clear(&e);
 *     pw_graph_init(&g, NULL, nnodes, nedges, &e);
 *     pw_graph_add_edge(&g, i, j, cap_ij, cap_ji, &e);     (n-links)
 *     pw_graph_add_tweights(&g, i, cap_source, cap_sink);  (t-links)
 *     pw_graph_maxflow(&g, &flow, &e);
 *     side = pw_graph_in_source(&g, i);
 *     pw_graph_free(&g);
 *
 * Capacities are doubles, >= 0; HUGE_VAL (infinity) is allowed for hard
 * constraints. The cut returned is the source side closest to the source:
 * exactly the nodes reachable from S through non-saturated arcs. Everything
 * is deterministic: the same calls give the same flow and the same cut.
 * With integer capacities below 2^53 every sum is exact. */
#ifndef PW__GRAPHCUT_V1
#define PW__GRAPHCUT_V1

#include "base.h"

/* Tree membership and parent markers. */
#define PW__GC_FREE 0
#define PW__GC_SOURCE 1
#define PW__GC_SINK 2
#define PW__GC_NOPARENT (-1) /* free node */
#define PW__GC_TERMINAL (-2) /* the parent is the tree's terminal */
#define PW__GC_ORPHAN (-3)   /* lost its parent arc in an augmentation */
#define PW__GC_IDLE (-2)     /* `next` of a node not in the active queue */

typedef struct pw__gc_node {
    double tr;  /* residual terminal capacity: > 0 from S, < 0 to T */
    int first;  /* first arc out of the node, -1 if none */
    int parent; /* arc from the node to its parent, or PW__GC_* above */
    int next;   /* next active node, -1 at the end, PW__GC_IDLE if not active */
    int ts;     /* time stamp at which dist was last known to be right */
    int dist;   /* arcs to the terminal of its tree */
    int tree;   /* PW__GC_FREE, _SOURCE or _SINK */
} pw__gc_node;

/* Arcs come in pairs: arc a and its reverse a ^ 1. The tail of a is the
 * head of a ^ 1, so it needs no storage. */
typedef struct pw__gc_arc {
    double rcap; /* residual capacity */
    int head;    /* node the arc points to */
    int next;    /* next arc out of the same tail, -1 at the end */
} pw__gc_arc;

typedef struct pw_graph {
    int nnodes;
    int narcs;          /* 2 per edge */
    pw__gc_node *nodes; /* nnodes */
    pw__gc_arc *arcs;   /* narcs, room for arc_cap */
    size_t arc_cap;
    int *orphans; /* nnodes: circular queue, each node at most once */
    int node_cap; /* nodes and orphans allocated */
    double flow;  /* flow so far, including common t-link parts */
    int active_first, active_last;
    int orphan_head, orphan_count;
    int time;   /* counts augmentations, for the ts of nodes */
    pw_err err; /* first invalid call, reported by pw_graph_maxflow */
    pw_alloc alloc;
} pw_graph;

/* Fills the node array for n free nodes without links. */
PW__DEF void pw__graph_clear_nodes(pw_graph *g)
{
    int i;
    for (i = 0; i < g->nnodes; i++) {
        pw__gc_node *v = &g->nodes[i];
        v->tr = 0;
        v->first = -1;
        v->parent = PW__GC_NOPARENT;
        v->next = PW__GC_IDLE;
        v->ts = 0;
        v->dist = 0;
        v->tree = PW__GC_FREE;
    }
}

/* Empties the graph and gives it nnodes nodes, keeping (and if needed
 * growing) the memory of an earlier graph. */
PW__DEF int pw_graph_reset(pw_graph *g, int nnodes, pw_err *e)
{
    if (nnodes < 0) return pw_fail(e, PW_ERR_INVALID, "graph: negative node count %d", nnodes);
    if (nnodes > g->node_cap || !g->nodes) {
        void *v = pw_realloc(&g->alloc, g->nodes, (size_t)nnodes * sizeof(pw__gc_node));
        void *o;
        if (!v) return pw_fail(e, PW_ERR_NOMEM, "graph: out of memory for %d nodes", nnodes);
        g->nodes = (pw__gc_node *)v;
        o = pw_realloc(&g->alloc, g->orphans, (size_t)nnodes * sizeof(int));
        if (!o) return pw_fail(e, PW_ERR_NOMEM, "graph: out of memory for %d nodes", nnodes);
        g->orphans = (int *)o;
        g->node_cap = nnodes;
    }
    g->nnodes = nnodes;
    g->narcs = 0;
    g->flow = 0;
    g->time = 0;
    pw_err_clear(&g->err);
    pw__graph_clear_nodes(g);
    return PW_OK;
}

PW__DEF void pw_graph_free(pw_graph *g)
{
    pw_alloc a = g->alloc;
    pw_free(&a, g->nodes);
    pw_free(&a, g->arcs);
    pw_free(&a, g->orphans);
    memset(g, 0, sizeof *g);
    g->alloc = a;
}

/* Creates a graph of nnodes nodes with room for nedges_hint edges (it grows
 * past that as needed). a may be NULL. */
PW__DEF int pw_graph_init(pw_graph *g, const pw_alloc *a, int nnodes, int nedges_hint, pw_err *e)
{
    int r;
    memset(g, 0, sizeof *g);
    if (a) g->alloc = *a;
    if ((r = pw_graph_reset(g, nnodes, e)) != PW_OK) {
        pw_graph_free(g);
        return r;
    }
    if (nedges_hint > 0 && nedges_hint < INT_MAX / 2 &&
        pw_grow(&g->alloc, (void **)&g->arcs, &g->arc_cap, (size_t)nedges_hint * 2, sizeof(pw__gc_arc), "graph edges",
                e)) {
        pw_graph_free(g);
        return PW_ERR_NOMEM;
    }
    return PW_OK;
}

/* Records an invalid call both in e and in the graph, so that a caller who
 * checks only pw_graph_maxflow still learns of it. */
PW__DEF int pw__graph_invalid(pw_graph *g, pw_err *e, int code, const char *what, int i, int j)
{
    if (j >= 0) pw_fail(&g->err, code, "graph edge (%d, %d): %s", i, j, what);
    else pw_fail(&g->err, code, "graph node %d: %s", i, what);
    return pw_fail(e, code, "%s", g->err.msg);
}

/* A capacity is valid if >= 0 and not NaN; +infinity is allowed. */
PW__DEF int pw__gc_cap_ok(double c) { return c >= 0; }

/* Adds the edge i-j with capacity cap_ij from i to j and cap_ji back.
 * Parallel edges add up. Fails on a bad index, a self loop or a negative or
 * NaN capacity. */
PW__DEF int pw_graph_add_edge(pw_graph *g, int i, int j, double cap_ij, double cap_ji, pw_err *e)
{
    pw__gc_arc *a;
    if (i < 0 || i >= g->nnodes || j < 0 || j >= g->nnodes)
        return pw__graph_invalid(g, e, PW_ERR_INVALID, "node index out of range", i, j);
    if (i == j) return pw__graph_invalid(g, e, PW_ERR_INVALID, "self loop", i, j);
    if (!pw__gc_cap_ok(cap_ij) || !pw__gc_cap_ok(cap_ji))
        return pw__graph_invalid(g, e, PW_ERR_INVALID, "negative or NaN capacity", i, j);
    if (g->narcs > INT_MAX - 2) return pw__graph_invalid(g, e, PW_ERR_LIMIT, "too many edges", i, j);
    if (pw_grow(&g->alloc, (void **)&g->arcs, &g->arc_cap, (size_t)g->narcs + 2, sizeof(pw__gc_arc), "graph edges",
                e)) {
        pw_fail(&g->err, PW_ERR_NOMEM, "graph: out of memory adding edge (%d, %d)", i, j);
        return PW_ERR_NOMEM;
    }
    a = &g->arcs[g->narcs];
    a[0].rcap = cap_ij;
    a[0].head = j;
    a[0].next = g->nodes[i].first;
    a[1].rcap = cap_ji;
    a[1].head = i;
    a[1].next = g->nodes[j].first;
    g->nodes[i].first = g->narcs;
    g->nodes[j].first = g->narcs + 1;
    g->narcs += 2;
    return PW_OK;
}

/* Adds capacities from the source to i and from i to the sink (they
 * accumulate over calls). Only the difference matters to the cut: the
 * common part min(source, sink) is flow that any cut pays, so it goes to
 * the flow at once and the node keeps a single net terminal capacity.
 * Returns PW_ERR_INVALID for a bad index or capacity (negative, NaN, or
 * infinite to both terminals); the error is also reported by
 * pw_graph_maxflow. */
PW__DEF int pw_graph_add_tweights(pw_graph *g, int i, double cap_source, double cap_sink)
{
    double t;
    if (i < 0 || i >= g->nnodes) return pw__graph_invalid(g, NULL, PW_ERR_INVALID, "node index out of range", i, -1);
    if (!pw__gc_cap_ok(cap_source) || !pw__gc_cap_ok(cap_sink))
        return pw__graph_invalid(g, NULL, PW_ERR_INVALID, "negative or NaN terminal capacity", i, -1);
    t = g->nodes[i].tr;
    if (t > 0) cap_source += t;
    else cap_sink -= t;
    if (cap_source == HUGE_VAL && cap_sink == HUGE_VAL)
        return pw__graph_invalid(g, NULL, PW_ERR_INVALID, "infinite capacity to both source and sink", i, -1);
    g->flow += cap_source < cap_sink ? cap_source : cap_sink;
    g->nodes[i].tr = cap_source - cap_sink;
    return PW_OK;
}

/* ---- the algorithm ------------------------------------------------------ */

/* Appends i to the active queue unless it is already there. */
PW__DEF void pw__gc_activate(pw_graph *g, int i)
{
    if (g->nodes[i].next != PW__GC_IDLE) return;
    g->nodes[i].next = -1;
    if (g->active_last >= 0) g->nodes[g->active_last].next = i;
    else g->active_first = i;
    g->active_last = i;
}

PW__DEF void pw__gc_pop_active(pw_graph *g)
{
    int i = g->active_first;
    g->active_first = g->nodes[i].next;
    if (g->active_first < 0) g->active_last = -1;
    g->nodes[i].next = PW__GC_IDLE;
}

/* The first active node still in a tree (nodes freed by adoption stay
 * queued and are dropped here), left at the front; -1 if none. */
PW__DEF int pw__gc_front(pw_graph *g)
{
    while (g->active_first >= 0) {
        int i = g->active_first;
        if (g->nodes[i].tree != PW__GC_FREE) return i;
        pw__gc_pop_active(g);
    }
    return -1;
}

PW__DEF void pw__gc_make_orphan(pw_graph *g, int i)
{
    int tail = g->orphan_head + g->orphan_count;
    g->nodes[i].parent = PW__GC_ORPHAN;
    if (tail >= g->nnodes) tail -= g->nnodes;
    g->orphans[tail] = i;
    g->orphan_count++;
}

/* Starts both trees from the nodes with a terminal capacity, in index
 * order. Residual capacities are kept, so calling pw_graph_maxflow again
 * (after adding capacity) continues from the current flow. */
PW__DEF void pw__gc_start(pw_graph *g)
{
    int i;
    g->active_first = g->active_last = -1;
    g->orphan_head = g->orphan_count = 0;
    g->time = 0;
    for (i = 0; i < g->nnodes; i++) {
        pw__gc_node *v = &g->nodes[i];
        v->next = PW__GC_IDLE;
        v->ts = 0;
        v->dist = 1;
        if (v->tr == 0) {
            v->tree = PW__GC_FREE;
            v->parent = PW__GC_NOPARENT;
            continue;
        }
        v->tree = v->tr > 0 ? PW__GC_SOURCE : PW__GC_SINK;
        v->parent = PW__GC_TERMINAL;
        pw__gc_activate(g, i);
    }
}

/* Growth stage from active node i: claims free neighbours reachable
 * through non-saturated arcs and returns the arc, oriented from the source
 * tree to the sink tree, where the trees touch (-1 if nowhere). */
PW__DEF int pw__gc_grow(pw_graph *g, int i)
{
    pw__gc_node *vi = &g->nodes[i];
    int a;
    for (a = vi->first; a >= 0; a = g->arcs[a].next) {
        /* arc in the direction flow would take: away from S, towards T */
        int fwd = vi->tree == PW__GC_SOURCE ? a : a ^ 1;
        pw__gc_node *vj;
        if (g->arcs[fwd].rcap <= 0) continue;
        vj = &g->nodes[g->arcs[a].head];
        if (vj->tree == PW__GC_FREE) {
            vj->tree = vi->tree;
            vj->parent = a ^ 1;
            vj->ts = vi->ts;
            vj->dist = vi->dist + 1;
            pw__gc_activate(g, g->arcs[a].head);
        } else if (vj->tree != vi->tree) {
            return fwd;
        } else if (vj->ts <= vi->ts && vj->dist > vi->dist) {
            /* A shorter way to the terminal through i keeps paths short.
             * Cannot close a cycle: along any tree path ts never decreases
             * towards the root and dist strictly decreases where ts is
             * equal, so i cannot be a descendant of j here. */
            vj->parent = a ^ 1;
            vj->ts = vi->ts;
            vj->dist = vi->dist + 1;
        }
    }
    return -1;
}

/* The smallest residual capacity on the path through arc mid: the arcs
 * to the source root, mid, the arcs to the sink root, and both terminal
 * links. */
PW__DEF double pw__gc_bottleneck(const pw_graph *g, int mid)
{
    const pw__gc_node *n = g->nodes;
    const pw__gc_arc *arc = g->arcs;
    double bn = arc[mid].rcap;
    int i, p;
    for (i = arc[mid ^ 1].head; (p = n[i].parent) != PW__GC_TERMINAL; i = arc[p].head)
        if (arc[p ^ 1].rcap < bn) bn = arc[p ^ 1].rcap; /* parent -> i carries the flow */
    if (n[i].tr < bn) bn = n[i].tr;
    for (i = arc[mid].head; (p = n[i].parent) != PW__GC_TERMINAL; i = arc[p].head)
        if (arc[p].rcap < bn) bn = arc[p].rcap; /* i -> parent carries the flow */
    if (-n[i].tr < bn) bn = -n[i].tr;
    return bn;
}

/* Pushes bn along the path through mid; nodes whose link to the parent
 * (or terminal) saturates become orphans. bn is the bottleneck, so every
 * subtraction below stays >= 0 and the bottleneck arc becomes exactly 0. */
PW__DEF void pw__gc_push(pw_graph *g, int mid, double bn)
{
    pw__gc_node *n = g->nodes;
    pw__gc_arc *arc = g->arcs;
    int i, p;
    arc[mid].rcap -= bn;
    arc[mid ^ 1].rcap += bn;
    for (i = arc[mid ^ 1].head; (p = n[i].parent) != PW__GC_TERMINAL; i = arc[p].head) {
        arc[p].rcap += bn;
        arc[p ^ 1].rcap -= bn;
        if (arc[p ^ 1].rcap == 0) pw__gc_make_orphan(g, i); /* parent stays readable in p */
    }
    n[i].tr -= bn;
    if (n[i].tr == 0) pw__gc_make_orphan(g, i);
    for (i = arc[mid].head; (p = n[i].parent) != PW__GC_TERMINAL; i = arc[p].head) {
        arc[p ^ 1].rcap += bn;
        arc[p].rcap -= bn;
        if (arc[p].rcap == 0) pw__gc_make_orphan(g, i);
    }
    n[i].tr += bn;
    if (n[i].tr == 0) pw__gc_make_orphan(g, i);
    g->flow += bn;
}

/* Distance from j to its tree's terminal if j's chain of parents reaches it
 * (INT_MAX if it meets an orphan). Nodes on a chain found valid are stamped
 * with the current time and their exact distance, so later searches in the
 * same adoption stage stop there. */
PW__DEF int pw__gc_root_dist(pw_graph *g, int j)
{
    pw__gc_node *n = g->nodes;
    int k = j, d = 0, total;
    for (;;) {
        int p;
        if (n[k].ts == g->time) {
            d += n[k].dist;
            break;
        }
        p = n[k].parent;
        d++;
        if (p == PW__GC_TERMINAL) {
            n[k].ts = g->time;
            n[k].dist = 1;
            break;
        }
        if (p < 0) return INT_MAX; /* orphan */
        k = g->arcs[p].head;
    }
    total = d;
    for (k = j; n[k].ts != g->time; k = g->arcs[n[k].parent].head) {
        n[k].ts = g->time;
        n[k].dist = d--;
    }
    return total;
}

/* Frees orphan i that found no parent: its children become orphans and
 * neighbours of its tree that could grow into it are reactivated. */
PW__DEF void pw__gc_free_orphan(pw_graph *g, int i)
{
    pw__gc_node *vi = &g->nodes[i];
    int a;
    for (a = vi->first; a >= 0; a = g->arcs[a].next) {
        int j = g->arcs[a].head, p;
        pw__gc_node *vj = &g->nodes[j];
        double into_i = vi->tree == PW__GC_SOURCE ? g->arcs[a ^ 1].rcap : g->arcs[a].rcap;
        if (vj->tree != vi->tree) continue;
        if (into_i > 0) pw__gc_activate(g, j);
        p = vj->parent;
        if (p >= 0 && g->arcs[p].head == i) pw__gc_make_orphan(g, j);
    }
    vi->tree = PW__GC_FREE;
    vi->parent = PW__GC_NOPARENT;
}

/* Adoption of orphan i: the neighbour of its own tree, linked to i by a
 * non-saturated arc and rooted at the terminal, that is closest to the
 * terminal becomes its parent; if there is none, i is freed. */
PW__DEF void pw__gc_adopt(pw_graph *g, int i)
{
    pw__gc_node *vi = &g->nodes[i];
    int a, best = -1, dbest = INT_MAX;
    for (a = vi->first; a >= 0; a = g->arcs[a].next) {
        pw__gc_node *vj = &g->nodes[g->arcs[a].head];
        /* flow would go j -> i in the source tree, i -> j in the sink tree */
        double c = vi->tree == PW__GC_SOURCE ? g->arcs[a ^ 1].rcap : g->arcs[a].rcap;
        int d;
        if (vj->tree != vi->tree || c <= 0) continue;
        d = pw__gc_root_dist(g, g->arcs[a].head);
        if (d < dbest) {
            dbest = d;
            best = a;
        }
    }
    if (best >= 0) {
        vi->parent = best;
        vi->ts = g->time;
        vi->dist = dbest + 1;
    } else {
        pw__gc_free_orphan(g, i);
    }
}

/* Augments along the path through mid and re-roots or frees the orphans.
 * Fails if the path has infinite capacity (unbounded flow). */
PW__DEF int pw__gc_augment(pw_graph *g, int mid, pw_err *e)
{
    double bn = pw__gc_bottleneck(g, mid);
    if (bn == HUGE_VAL) {
        g->flow = HUGE_VAL;
        return pw_fail(e, PW_ERR_INVALID,
                       "graph: a path of infinite capacity joins the "
                       "source to the sink (through nodes %d and %d): the flow is unbounded",
                       g->arcs[mid ^ 1].head, g->arcs[mid].head);
    }
    if (++g->time == INT_MAX) { /* keep ts comparisons valid: forget all stamps */
        int i;
        for (i = 0; i < g->nnodes; i++) g->nodes[i].ts = 0;
        g->time = 1;
    }
    pw__gc_push(g, mid, bn);
    while (g->orphan_count > 0) {
        int i = g->orphans[g->orphan_head];
        if (++g->orphan_head == g->nnodes) g->orphan_head = 0;
        g->orphan_count--;
        pw__gc_adopt(g, i);
    }
    return PW_OK;
}

/* Computes the maximum flow from the source to the sink, which equals the
 * capacity of the minimum cut, into *flow (may be NULL); afterwards
 * pw_graph_in_source tells each node's side. Fails with the first error of
 * an earlier add_edge/add_tweights call, or PW_ERR_INVALID if an
 * infinite-capacity path joins the terminals. */
PW__DEF int pw_graph_maxflow(pw_graph *g, double *flow, pw_err *e)
{
    int i, mid;
    if (flow) *flow = 0;
    if (g->err.code) return pw_fail(e, g->err.code, "%s", g->err.msg);
    pw__gc_start(g);
    while ((i = pw__gc_front(g)) >= 0) {
        mid = pw__gc_grow(g, i);
        if (mid < 0) {
            pw__gc_pop_active(g); /* fully grown; i stays in its tree */
            continue;
        }
        /* i stays at the front: after the augmentation it may touch the
         * other tree through another arc */
        if (pw__gc_augment(g, mid, e)) return PW_ERR_INVALID;
    }
    if (flow) *flow = g->flow;
    return PW_OK;
}

/* 1 if node i is on the source side of the minimum cut found by the last
 * pw_graph_maxflow (the nodes reachable from the source through
 * non-saturated arcs), 0 otherwise or if i is out of range. */
PW__DEF int pw_graph_in_source(const pw_graph *g, int i)
{
    if (i < 0 || i >= g->nnodes) return 0;
    return g->nodes[i].tree == PW__GC_SOURCE;
}

#endif /* PW__GRAPHCUT_V1 */
