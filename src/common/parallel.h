/* parallel: a parallel for, the one way work is split across threads.
 *
 *   pw_parallel      where work runs: the caller's parallel-for (an
 *                    embedder's job system), POSIX threads when built with
 *                    PW_THREADS, or the calling thread alone.
 *   pw_parallel_for  runs task(ctx, i) for every i in [0, n) as it says.
 *   pw_parallel_width how many tasks may run at once.
 *   pw_parallel_start, pw_parallel_stop  keep the POSIX threads between
 *                    parallel-fors (a crew, for work made of many short
 *                    parallel-fors); without them each one starts its own.
 *
 * Every user (rendering bands, tile synthesis, ...) makes each task write
 * its own part of the output and combines the parts in index order, so a
 * result is the same, bit for bit, for any number of threads. */
#ifndef PW__PARALLEL_V1
#define PW__PARALLEL_V1

#include "base.h"

/* A parallel for: runs task(ctx, i) once for every i in [0, n), in any
 * order, on any threads, and returns when all have run. Results never
 * depend on the order (each task writes its own part of the output). */
typedef void (*pw_task_fn)(void *ctx, int index);
typedef void (*pw_parallel_fn)(void *pool, int n, pw_task_fn task, void *ctx);

/* Where work runs: the caller's parallel for (run, pool: an embedder's job
 * system), else with PW_THREADS `threads` POSIX threads (0: one per
 * processor), else one thread. */
typedef struct pw_parallel {
    pw_parallel_fn run;
    void *pool;
    int threads;
    struct pw__crew *crew; /* with PW_THREADS, between pw_parallel_start and _stop */
} pw_parallel;

/* The pw_parallel of a public options struct's threads, parallel-for and
 * pool. */
PW__DEF pw_parallel pw_parallel_make(int threads, pw_parallel_fn run, void *pool)
{
    pw_parallel par;
    par.threads = threads;
    par.run = run;
    par.pool = pool;
    par.crew = NULL;
    return par;
}

#ifdef PW_THREADS
#include <pthread.h>
#include <unistd.h>

/* One parallel for on POSIX threads. The caller waits for the tasks, not
 * for the threads: a thread that starts late (the processors busy with
 * other work) finds nothing left and leaves, and the last one out frees
 * the pool (refs counts the caller and every started thread). */
typedef struct pw__pool {
    pthread_mutex_t lock;
    pthread_cond_t finished;
    int next, n, done, refs;
    pw_task_fn task;
    void *ctx;
} pw__pool;

/* Drops one reference to p; the last frees it. */
PW__DEF void pw__pool_release(pw__pool *p)
{
    int last;
    pthread_mutex_lock(&p->lock);
    last = --p->refs == 0;
    pthread_mutex_unlock(&p->lock);
    if (last) {
        pthread_cond_destroy(&p->finished);
        pthread_mutex_destroy(&p->lock);
        PW_FREE(p);
    }
}

/* Runs tasks until none is left to claim. */
PW__DEF void pw__pool_work(pw__pool *p)
{
    for (;;) {
        int i;
        pthread_mutex_lock(&p->lock);
        i = p->next < p->n ? p->next++ : -1;
        pthread_mutex_unlock(&p->lock);
        if (i < 0) return;
        p->task(p->ctx, i);
        pthread_mutex_lock(&p->lock);
        if (++p->done == p->n) pthread_cond_signal(&p->finished);
        pthread_mutex_unlock(&p->lock);
    }
}

PW__DEF void *pw__pool_worker(void *arg)
{
    pw__pool_work((pw__pool *)arg);
    pw__pool_release((pw__pool *)arg);
    return NULL;
}

/* n tasks on up to `threads` threads (0: one per processor); the calling
 * thread works too. Falls back to fewer threads if some cannot start. */
PW__DEF void pw__pool_run(int threads, int n, pw_task_fn task, void *ctx)
{
    pthread_attr_t attr;
    pthread_t th;
    pw__pool *p = (pw__pool *)PW_MALLOC(sizeof(pw__pool));
    int k;
    if (threads <= 0) {
        long np = sysconf(_SC_NPROCESSORS_ONLN);
        threads = np > 0 ? (int)np : 1;
    }
    if (threads > n) threads = n;
    if (threads > 64) threads = 64;
    if (!p || pthread_attr_init(&attr) != 0) {
        PW_FREE(p);
        for (k = 0; k < n; k++) task(ctx, k);
        return;
    }
    p->next = p->done = 0;
    p->n = n;
    p->refs = 1;
    p->task = task;
    p->ctx = ctx;
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->finished, NULL);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    for (k = 1; k < threads; k++) {
        pthread_mutex_lock(&p->lock);
        p->refs++;
        pthread_mutex_unlock(&p->lock);
        if (pthread_create(&th, &attr, pw__pool_worker, p) != 0) pw__pool_release(p);
    }
    pthread_attr_destroy(&attr);
    pw__pool_work(p);
    pthread_mutex_lock(&p->lock);
    while (p->done < p->n) pthread_cond_wait(&p->finished, &p->lock);
    pthread_mutex_unlock(&p->lock);
    pw__pool_release(p);
}
/* A crew: POSIX threads kept between parallel-fors (pw_parallel_start),
 * each asleep until the caller hands out a task set. The caller works on
 * the set too, and returns when all its tasks have run. gen counts the
 * sets handed out (and the stop): a thread that has seen set `seen` waits
 * for gen to move, spinning first, then asleep. The spin is long:
 * PW_CREW_SPIN pause instructions, 2,000,000 by default (about 30 ms on
 * the 2-core Xeon of bench/results.md, 15 ns a pause). The methods hand
 * out many small sets between serial steps (lapped_create paints each
 * paste, ~0.25 ms of work, after ~1 ms of growth; lst_create covers each
 * clump, ~0.1 ms): a thread woken from its condition variable arrives
 * tens of microseconds late, a good part of such a set, so a short spin
 * (20,000 pauses: 0.3 ms) left the coverage at 1.40-1.59 times faster on 2
 * threads, the long one at 1.70-1.84 (bunny00, bench_threads). The cost:
 * while a crew lives (one create or render call, pw_parallel_start to
 * pw_parallel_stop) its threads keep their cores busy between sets.
 * Define PW_CREW_SPIN smaller (0: no spin) where that matters more. */
typedef struct pw__crew {
    pthread_mutex_t lock;
    pthread_cond_t wake, finished;
    pw_task_fn task;
    void *ctx;
    int next, n, done; /* the set under way: tasks claimed, in all, finished */
    unsigned gen;
    int busy, quit, nthreads;
    pthread_t th[64];
} pw__crew;

/* gen and done are read outside the lock while spinning: atomically where
 * the compiler has the builtins, else not at all (no spin). */
#if defined(__GNUC__) || defined(__clang__)
#ifndef PW_CREW_SPIN
#define PW_CREW_SPIN 2000000
#endif
#define PW__CREW_SPIN PW_CREW_SPIN
#define PW__CREW_PEEK(x) __atomic_load_n(&(x), __ATOMIC_ACQUIRE)
#define PW__CREW_SET(x, v) __atomic_store_n(&(x), (v), __ATOMIC_RELEASE)
#if defined(__x86_64__) || defined(__i386__)
#define PW__CREW_PAUSE() __builtin_ia32_pause()
#elif defined(__aarch64__)
#define PW__CREW_PAUSE() __asm__ __volatile__("yield")
#else
#define PW__CREW_PAUSE() ((void)0)
#endif
#else
#define PW__CREW_SPIN 0
#define PW__CREW_PEEK(x) (x)
#define PW__CREW_SET(x, v) ((x) = (v))
#define PW__CREW_PAUSE() ((void)0)
#endif

/* Runs the set's tasks until none is left to claim; called, and returns,
 * with the lock held. */
PW__DEF void pw__crew_work(pw__crew *c)
{
    while (c->next < c->n) {
        int i = c->next++;
        pw_task_fn task = c->task;
        void *ctx = c->ctx;
        pthread_mutex_unlock(&c->lock);
        task(ctx, i);
        pthread_mutex_lock(&c->lock);
        PW__CREW_SET(c->done, c->done + 1);
        if (c->done == c->n) pthread_cond_signal(&c->finished);
    }
}

PW__DEF void *pw__crew_main(void *arg)
{
    pw__crew *c = (pw__crew *)arg;
    unsigned seen = 0;
    int k;
    pthread_mutex_lock(&c->lock);
    for (;;) {
        if (c->gen == seen) {
            pthread_mutex_unlock(&c->lock);
            for (k = 0; k < PW__CREW_SPIN && PW__CREW_PEEK(c->gen) == seen; k++) PW__CREW_PAUSE();
            pthread_mutex_lock(&c->lock);
        }
        while (c->gen == seen) pthread_cond_wait(&c->wake, &c->lock);
        if (c->quit) break;
        seen = c->gen;
        pw__crew_work(c);
    }
    pthread_mutex_unlock(&c->lock);
    return NULL;
}

/* n tasks on the crew and the calling thread; 0 (nothing run) when the
 * crew is already running a set (a task's own parallel-for, or another
 * thread's). */
PW__DEF int pw__crew_run(pw__crew *c, int n, pw_task_fn task, void *ctx)
{
    int k;
    pthread_mutex_lock(&c->lock);
    if (c->busy) {
        pthread_mutex_unlock(&c->lock);
        return 0;
    }
    c->busy = 1;
    c->task = task;
    c->ctx = ctx;
    c->next = 0;
    c->n = n;
    PW__CREW_SET(c->done, 0);
    PW__CREW_SET(c->gen, c->gen + 1);
    pthread_cond_broadcast(&c->wake);
    pw__crew_work(c);
    if (c->done < n) {
        pthread_mutex_unlock(&c->lock);
        for (k = 0; k < PW__CREW_SPIN && PW__CREW_PEEK(c->done) < n; k++) PW__CREW_PAUSE();
        pthread_mutex_lock(&c->lock);
    }
    while (c->done < n) pthread_cond_wait(&c->finished, &c->lock);
    c->busy = 0;
    pthread_mutex_unlock(&c->lock);
    return 1;
}
#endif

/* The number of tasks that may run at once under par. */
PW__DEF int pw_parallel_width(const pw_parallel *par)
{
    if (!par || par->threads == 1) return 1;
    if (par->run) return par->threads > 1 ? par->threads : 8;
#ifdef PW_THREADS
    if (par->threads > 1) return par->threads;
    {
        long np = sysconf(_SC_NPROCESSORS_ONLN);
        return np > 1 ? (int)np : 1;
    }
#else
    return 1;
#endif
}

/* Stops par's crew, if any: its threads end and are joined. */
PW__DEF void pw_parallel_stop(pw_parallel *par)
{
#ifdef PW_THREADS
    pw__crew *c = par ? par->crew : NULL;
    int k;
    if (!c) return;
    pthread_mutex_lock(&c->lock);
    c->quit = 1;
    PW__CREW_SET(c->gen, c->gen + 1);
    pthread_cond_broadcast(&c->wake);
    pthread_mutex_unlock(&c->lock);
    for (k = 0; k < c->nthreads; k++) pthread_join(c->th[k], NULL);
    pthread_cond_destroy(&c->finished);
    pthread_cond_destroy(&c->wake);
    pthread_mutex_destroy(&c->lock);
    PW_FREE(c);
    par->crew = NULL;
#else
    (void)par;
#endif
}

/* Starts a crew for par (with PW_THREADS, POSIX threads: not for a
 * caller's parallel-for or one thread), so that the parallel-fors until
 * pw_parallel_stop wake threads instead of starting them. Without a crew
 * (no PW_THREADS, or threads that cannot start) they run as before. */
PW__DEF void pw_parallel_start(pw_parallel *par)
{
#ifdef PW_THREADS
    pw__crew *c;
    int width = pw_parallel_width(par);
    if (!par || par->run || par->crew || width < 2) return;
    if (!(c = (pw__crew *)PW_MALLOC(sizeof(pw__crew)))) return;
    memset(c, 0, sizeof *c);
    pthread_mutex_init(&c->lock, NULL);
    pthread_cond_init(&c->wake, NULL);
    pthread_cond_init(&c->finished, NULL);
    for (width = width > 64 ? 64 : width; c->nthreads < width - 1; c->nthreads++)
        if (pthread_create(&c->th[c->nthreads], NULL, pw__crew_main, c) != 0) break;
    par->crew = c;
    if (c->nthreads == 0) pw_parallel_stop(par);
#else
    (void)par;
#endif
}

/* Runs task(ctx, i) for i in [0, n) as par says (NULL: in order, here). */
PW__DEF void pw_parallel_for(const pw_parallel *par, int n, pw_task_fn task, void *ctx)
{
    int i;
    if (n <= 0) return;
    if (par && par->run && par->threads != 1) {
        par->run(par->pool, n, task, ctx);
        return;
    }
#ifdef PW_THREADS
    if (par && par->crew && n > 1 && pw__crew_run(par->crew, n, task, ctx)) return;
    if (par && par->threads != 1 && n > 1) {
        pw__pool_run(par->threads, n, task, ctx);
        return;
    }
#endif
    for (i = 0; i < n; i++) task(ctx, i);
}

#endif /* PW__PARALLEL_V1 */
