/* heap: a binary min-heap of (key, item) pairs, ties broken by the smaller
 * item, so that the order in which entries come out depends on nothing but
 * the entries (Dijkstra's distances over a mesh, region growing by
 * distance). Equal pairs are interchangeable, so every correct heap pops
 * the same sequence: the methods' results do not depend on this code's
 * sifting. The arrays grow (pw_heap_push) or are the caller's, of a
 * capacity it knows (pw_heap_insert). */
#ifndef PW__HEAP_V1
#define PW__HEAP_V1

#include "base.h"

typedef struct pw_heap {
    double *key;
    int *item;
    int n;             /* entries */
    size_t kcap, icap; /* capacities of key and item, for pw_heap_push */
} pw_heap;

/* Whether entry i comes out before entry j. */
PW__DEF int pw_heap_before(const pw_heap *h, int i, int j)
{
    return h->key[i] < h->key[j] || (h->key[i] == h->key[j] && h->item[i] < h->item[j]);
}

PW__DEF void pw__heap_swap(pw_heap *h, int i, int j)
{
    double k = h->key[i];
    int t = h->item[i];
    h->key[i] = h->key[j];
    h->item[i] = h->item[j];
    h->key[j] = k;
    h->item[j] = t;
}

/* Adds an entry; the arrays must have room for it. */
PW__DEF void pw_heap_insert(pw_heap *h, double key, int item)
{
    int i = h->n++;
    h->key[i] = key;
    h->item[i] = item;
    while (i > 0 && pw_heap_before(h, i, (i - 1) / 2)) {
        pw__heap_swap(h, i, (i - 1) / 2);
        i = (i - 1) / 2;
    }
}

/* Adds an entry, growing the arrays. */
PW__DEF int pw_heap_push(const pw_alloc *a, pw_heap *h, double key, int item, pw_err *e)
{
    if (pw_grow(a, (void **)&h->key, &h->kcap, (size_t)h->n + 1, sizeof(double), "queue", e) ||
        pw_grow(a, (void **)&h->item, &h->icap, (size_t)h->n + 1, sizeof(int), "queue", e))
        return PW_ERR_NOMEM;
    pw_heap_insert(h, key, item);
    return PW_OK;
}

/* Removes the first entry (key[0], item[0]; n > 0) and returns its item. */
PW__DEF int pw_heap_pop(pw_heap *h)
{
    int top = h->item[0], i = 0;
    h->n--;
    h->key[0] = h->key[h->n];
    h->item[0] = h->item[h->n];
    for (;;) {
        int l = 2 * i + 1, r = l + 1, s = i;
        if (l < h->n && pw_heap_before(h, l, s)) s = l;
        if (r < h->n && pw_heap_before(h, r, s)) s = r;
        if (s == i) break;
        pw__heap_swap(h, i, s);
        i = s;
    }
    return top;
}

/* Frees arrays that pw_heap_push grew. */
PW__DEF void pw_heap_free(const pw_alloc *a, pw_heap *h)
{
    pw_free(a, h->key);
    pw_free(a, h->item);
    memset(h, 0, sizeof *h);
}

#endif /* PW__HEAP_V1 */
