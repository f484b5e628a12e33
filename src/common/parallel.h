/* parallel: a parallel for, the one way work is split across threads.
 *
 *   pw_parallel      where work runs: the caller's parallel-for (an
 *                    embedder's job system), POSIX threads when built with
 *                    PW_THREADS, or the calling thread alone.
 *   pw_parallel_for  runs task(ctx, i) for every i in [0, n) as it says.
 *   pw_parallel_width how many tasks may run at once.
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
} pw_parallel;

/* The pw_parallel of a public options struct's threads, parallel-for and
 * pool. */
PW__DEF pw_parallel pw_parallel_make(int threads, pw_parallel_fn run, void *pool)
{
    pw_parallel par;
    par.threads = threads;
    par.run = run;
    par.pool = pool;
    return par;
}

#ifdef PW_THREADS
#include <pthread.h>
#include <unistd.h>

typedef struct pw__pool {
    pthread_mutex_t lock;
    int next, n;
    pw_task_fn task;
    void *ctx;
} pw__pool;

PW__DEF void *pw__pool_worker(void *arg)
{
    pw__pool *p = (pw__pool *)arg;
    for (;;) {
        int i;
        pthread_mutex_lock(&p->lock);
        i = p->next < p->n ? p->next++ : -1;
        pthread_mutex_unlock(&p->lock);
        if (i < 0) return NULL;
        p->task(p->ctx, i);
    }
}

/* n tasks on up to `threads` threads (0: one per processor); the calling
 * thread works too. Falls back to fewer threads if some cannot start. */
PW__DEF void pw__pool_run(int threads, int n, pw_task_fn task, void *ctx)
{
    pthread_t th[64];
    pw__pool p;
    int k, started = 0;
    if (threads <= 0) {
        long np = sysconf(_SC_NPROCESSORS_ONLN);
        threads = np > 0 ? (int)np : 1;
    }
    if (threads > n) threads = n;
    if (threads > 64) threads = 64;
    p.next = 0;
    p.n = n;
    p.task = task;
    p.ctx = ctx;
    pthread_mutex_init(&p.lock, NULL);
    for (k = 1; k < threads; k++)
        if (pthread_create(&th[started], NULL, pw__pool_worker, &p) == 0) started++;
    pw__pool_worker(&p);
    for (k = 0; k < started; k++) pthread_join(th[k], NULL);
    pthread_mutex_destroy(&p.lock);
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
    if (par && par->threads != 1 && n > 1) {
        pw__pool_run(par->threads, n, task, ctx);
        return;
    }
#endif
    for (i = 0; i < n; i++) task(ctx, i);
}

#endif /* PW__PARALLEL_V1 */
