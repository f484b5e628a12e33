/* text: locale-independent number parsing and formatting, a line scanner
 * for text formats (with line numbers for error messages) and a buffered
 * writer over pw_write_fn. Used by every text reader and writer: OBJ, OFF,
 * PLY headers, paste files, constraint files, TetGen and MEDIT files. */
#ifndef PW__TEXT_V1
#define PW__TEXT_V1

#include "base.h"

/* ---- number parsing ------------------------------------------------------ */

static const double pw__num_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                         1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* v * 10^x with exact powers of ten (deterministic: only + - * /). */
PW__DEF double pw__num_mul10(double v, int x)
{
    while (x > 22) {
        v *= 1e22;
        x -= 22;
    }
    while (x < -22) {
        v /= 1e22;
        x += 22;
    }
    return x >= 0 ? v * pw__num_pow10[x] : v / pw__num_pow10[-x];
}

/* m * 10^x. Powers of ten up to 1e22 are exact doubles, so the common case
 * (up to 17 significant digits, small exponent) is one rounding, and the
 * shortest "%.9g" text of a float reads back to the same float. */
PW__DEF double pw__num_scale10(uint64_t m, long x, int neg)
{
    double v = (double)m;
    if (m == 0) x = 0;
    if (x > 400) v = HUGE_VAL;  /* m >= 1, so at least 1e400 */
    else if (x < -400) v = 0.0; /* m < 1e18, so below 1e-382 */
    else v = pw__num_mul10(v, (int)x);
    return neg ? -v : v;
}

/* "nan", "inf", "infinity" in any case: parsed so that readers can report a
 * non-finite coordinate rather than a malformed number. */
PW__DEF const char *pw__num_special(const char *p, const char *end, double *out, int neg)
{
    static const char *const words[3] = {"infinity", "inf", "nan"};
    int k;
    for (k = 0; k < 3; k++) {
        size_t n = strlen(words[k]), i;
        if ((size_t)(end - p) < n) continue;
        for (i = 0; i < n && (p[i] | 32) == words[k][i]; i++) {
        }
        if (i < n) continue;
        *out = k < 2 ? (neg ? -HUGE_VAL : HUGE_VAL) : (double)NAN;
        return p + n;
    }
    return NULL;
}

/* Parses a decimal number in [p, end) into *out; returns the first byte
 * after it, or NULL when there is no number. Locale-independent, and needs
 * no NUL terminator (strtod needs both a terminator and the C locale). */
PW__DEF const char *pw__num_parse(const char *p, const char *end, double *out)
{
    uint64_t m = 0;
    long x = 0, ex = 0;
    int neg = 0, digits = 0, eneg = 0, ed = 0;
    if (p < end && (*p == '+' || *p == '-')) neg = *p++ == '-';
    if (p < end && ((*p | 32) == 'n' || (*p | 32) == 'i')) return pw__num_special(p, end, out, neg);
    for (; p < end && *p >= '0' && *p <= '9'; p++, digits++) {
        if (m < 100000000000000000ULL) m = m * 10 + (uint64_t)(*p - '0');
        else if (x < 100000) x++; /* digits past the 17th only scale */
    }
    if (p < end && *p == '.')
        for (p++; p < end && *p >= '0' && *p <= '9'; p++, digits++)
            if (m < 100000000000000000ULL) {
                m = m * 10 + (uint64_t)(*p - '0');
                x--;
            }
    if (!digits) return NULL;
    if (p < end && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < end && (*p == '+' || *p == '-')) eneg = *p++ == '-';
        for (; p < end && *p >= '0' && *p <= '9'; p++, ed++)
            if (ex < 100000) ex = ex * 10 + (*p - '0');
        if (!ed) return NULL;
    }
    *out = pw__num_scale10(m, x + (eneg ? -ex : ex), neg);
    return p;
}

/* A double narrowed to float, rounding to nearest; values that would round
 * past FLT_MAX become infinite (a plain cast of them is undefined
 * behaviour), and readers then refuse them as non-finite. */
PW__DEF float pw__num_to_float(double v)
{
    const double overflow = 3.4028235677973366e38; /* FLT_MAX + half an ulp */
    if (v > FLT_MAX) return v < overflow ? FLT_MAX : (float)HUGE_VAL;
    if (v < -FLT_MAX) return v > -overflow ? -FLT_MAX : -(float)HUGE_VAL;
    return (float)v;
}

/* Decimal integer with optional sign, saturating at +-1e15 (callers compare
 * against much smaller limits). */
PW__DEF const char *pw__num_parse_int(const char *p, const char *end, long long *out)
{
    long long v = 0;
    int neg = 0, digits = 0;
    if (p < end && (*p == '+' || *p == '-')) neg = *p++ == '-';
    for (; p < end && *p >= '0' && *p <= '9'; p++, digits++)
        if (v < 1000000000000000LL) v = v * 10 + (*p - '0');
    if (!digits) return NULL;
    *out = neg ? -v : v;
    return p;
}

/* ---- text scanning ------------------------------------------------------- */

/* A cursor over text, tracking the line for messages. `cont` makes
 * backslash-newline a blank (OBJ line continuation). */
typedef struct pw__sc {
    const char *p, *end, *name;
    int line, cont;
    pw_err *e;
} pw__sc;

PW__DEF void pw__sc_init(pw__sc *s, const void *data, size_t size, const char *name, int cont, pw_err *e)
{
    s->p = (const char *)data;
    s->end = s->p + size;
    s->name = name ? name : "<memory>";
    s->line = 1;
    s->cont = cont;
    s->e = e;
    if (size >= 3 && !memcmp(s->p, "\xEF\xBB\xBF", 3)) s->p += 3; /* UTF-8 byte order mark */
}

/* Records an error prefixed with "name:line: ". */
PW__DEF int pw__sc_fail(pw__sc *s, int code, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return pw_fail(s->e, code, "%s:%d: %s", s->name, s->line, msg);
}

PW__DEF int pw__sc_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* Skips blanks on the current line (and continuations when enabled). */
PW__DEF void pw__sc_blank(pw__sc *s)
{
    for (;;) {
        const char *q;
        while (s->p < s->end && pw__sc_blank_char(*s->p)) s->p++;
        if (!s->cont || s->p >= s->end || *s->p != '\\') return;
        for (q = s->p + 1; q < s->end && pw__sc_blank_char(*q); q++) {
        }
        if (q < s->end && *q != '\n') return; /* a backslash inside a token */
        s->p = q < s->end ? q + 1 : q;
        s->line += q < s->end;
    }
}

/* True at the end of the logical line: newline, comment or end of data. */
PW__DEF int pw__sc_eol(pw__sc *s)
{
    pw__sc_blank(s);
    return s->p >= s->end || *s->p == '\n' || *s->p == '#';
}

/* Moves past the end of the current logical line. */
PW__DEF void pw__sc_next_line(pw__sc *s)
{
    for (;;) {
        pw__sc_blank(s);
        if (s->p >= s->end) return;
        if (*s->p++ == '\n') {
            s->line++;
            return;
        }
    }
}

/* Skips blank and comment-only lines. */
PW__DEF void pw__sc_skip_empty(pw__sc *s)
{
    while (pw__sc_eol(s) && s->p < s->end) pw__sc_next_line(s);
}

/* Skips blanks and newlines (for token streams such as ASCII PLY data). */
PW__DEF void pw__sc_skip_ws(pw__sc *s)
{
    for (; s->p < s->end && (pw__sc_blank_char(*s->p) || *s->p == '\n'); s->p++)
        if (*s->p == '\n') s->line++;
}

PW__DEF int pw__sc_delim(const pw__sc *s, const char *q)
{
    return q >= s->end || pw__sc_blank_char(*q) || *q == '\n' || *q == '#' || (s->cont && *q == '\\');
}

/* The next word on the line (up to a blank, newline or '#'); n = 0 at eol. */
PW__DEF const char *pw__sc_word(pw__sc *s, size_t *n)
{
    const char *w;
    pw__sc_blank(s);
    for (w = s->p; s->p < s->end && !pw__sc_delim(s, s->p); s->p++) {
    }
    *n = (size_t)(s->p - w);
    return w;
}

PW__DEF int pw__sc_is(const char *w, size_t n, const char *lit) { return strlen(lit) == n && !memcmp(w, lit, n); }

/* Copies the token at q, shortened and made printable, for messages. */
PW__DEF const char *pw__sc_tok(const pw__sc *s, const char *q, char *buf)
{
    int n = 0;
    while (q < s->end && n < 24 && !pw__sc_blank_char(*q) && *q != '\n') {
        buf[n++] = (*q >= 32 && *q < 127) ? *q : '?';
        q++;
    }
    if (n == 24) buf[n - 1] = buf[n - 2] = buf[n - 3] = '.';
    buf[n] = 0;
    return buf;
}

/* The error of pw__sc_value, naming `what` and its index (if >= 0). */
PW__DEF int pw__sc_value_error(pw__sc *s, int missing, int is_int, const char *what, long long index)
{
    char tok[32], label[64];
    if (index >= 0) snprintf(label, sizeof label, "%s %lld", what, index);
    else snprintf(label, sizeof label, "%s", what);
    if (missing) return pw__sc_fail(s, PW_ERR_PARSE, "%s: %s is missing", label, is_int ? "an integer" : "a number");
    return pw__sc_fail(s, PW_ERR_PARSE, "%s: malformed %s '%s'", label, is_int ? "integer" : "number",
                       pw__sc_tok(s, s->p, tok));
}

/* Reads one number (d) or integer (i) on the current line: 0, or an error
 * naming `what` and its index (e.g. "vertex 12"; index < 0: none) when it
 * is missing or malformed. */
PW__DEF int pw__sc_value(pw__sc *s, double *d, long long *i, const char *what, long long index)
{
    const char *q;
    if (pw__sc_eol(s)) return pw__sc_value_error(s, 1, !d, what, index);
    q = d ? pw__num_parse(s->p, s->end, d) : pw__num_parse_int(s->p, s->end, i);
    if (!q || !pw__sc_delim(s, q)) return pw__sc_value_error(s, 0, !d, what, index);
    s->p = q;
    return PW_OK;
}
PW__DEF int pw__sc_num(pw__sc *s, double *v, const char *what, long long index)
{
    return pw__sc_value(s, v, NULL, what, index);
}
PW__DEF int pw__sc_int(pw__sc *s, long long *v, const char *what, long long index)
{
    return pw__sc_value(s, NULL, v, what, index);
}

/* Reads the line "<keyword> n1 ... nk" (after blank and comment lines), each
 * integer within [lo, hi], and moves to the next line. */
PW__DEF int pw__sc_read_ints(pw__sc *s, const char *keyword, long long *v, int n, long long lo, long long hi)
{
    size_t len;
    const char *w;
    int k, r;
    pw__sc_skip_empty(s);
    w = pw__sc_word(s, &len);
    if (!pw__sc_is(w, len, keyword)) return pw__sc_fail(s, PW_ERR_PARSE, "expected '%s'", keyword);
    for (k = 0; k < n; k++) {
        if ((r = pw__sc_int(s, &v[k], keyword, -1)) != PW_OK) return r;
        if (v[k] < lo || v[k] > hi)
            return pw__sc_fail(s, PW_ERR_LIMIT, "%s: %lld is outside %lld..%lld", keyword, v[k], lo, hi);
    }
    if (!pw__sc_eol(s)) return pw__sc_fail(s, PW_ERR_PARSE, "unexpected text after '%s'", keyword);
    pw__sc_next_line(s);
    return PW_OK;
}

/* Buffered output over a pw_write_fn. */
typedef struct pw__wb {
    pw_write_fn w;
    void *ctx;
    size_t n;
    int failed;
    char buf[4096];
} pw__wb;

PW__DEF void pw__wb_flush(pw__wb *b)
{
    if (b->n && !b->failed && b->w(b->ctx, b->buf, b->n) != 0) b->failed = 1;
    b->n = 0;
}

PW__DEF void pw__wb_put(pw__wb *b, const char *s, size_t n)
{
    while (n) {
        size_t k = sizeof b->buf - b->n < n ? sizeof b->buf - b->n : n;
        memcpy(b->buf + b->n, s, k);
        b->n += k;
        s += k;
        n -= k;
        if (b->n == sizeof b->buf) pw__wb_flush(b);
    }
}

PW__DEF void pw__wb_str(pw__wb *b, const char *s) { pw__wb_put(b, s, strlen(s)); }

/* " %d" without printf. */
PW__DEF void pw__wb_int(pw__wb *b, long long v, char lead)
{
    char t[24];
    int n = (int)sizeof t;
    unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    do t[--n] = (char)('0' + u % 10);
    while (u /= 10);
    if (v < 0) t[--n] = '-';
    if (lead) t[--n] = lead;
    pw__wb_put(b, t + n, sizeof t - (size_t)n);
}

/* Nine significant digits of |x| > 0 as an integer in [1e8, 1e9), and the
 * decimal exponent of the first digit. The first guess of the exponent
 * comes from the binary one and is corrected by at most a step. */
PW__DEF uint32_t pw__num_digits(double x, int *e10)
{
    int e2, k, t;
    uint32_t d = 0;
    frexp(x, &e2);        /* x in [2^(e2-1), 2^e2) */
    t = (e2 - 1) * 30103; /* log10(2) = 0.30103 */
    *e10 = t >= 0 ? t / 100000 : -((99999 - t) / 100000);
    for (k = 0; k < 4; k++) {
        double m = pw__num_mul10(x, 8 - *e10), fl = floor(m);
        /* round half to even, like printf: exact ties are common (x is a
         * dyadic fraction and the product is then exact) */
        fl += m - fl > 0.5 || (m - fl == 0.5 && fmod(fl, 2.0) != 0.0);
        d = fl >= 1e9 ? 1000000000u : (uint32_t)fl;
        if (d >= 1000000000u) ++*e10;
        else if (d < 100000000u) --*e10;
        else break;
    }
    return d;
}

/* Formats a finite float with 9 significant digits, the most a float
 * needs to read back exactly, without printf: locale-independent (never a
 * decimal comma) and several times faster. Returns the length. */
PW__DEF int pw__num_format(char *out, float xf)
{
    char dig[10];
    double x = xf;
    uint32_t d, bits;
    int n = 0, nd = 9, e10, i, pos;
    memcpy(&bits, &xf, 4);
    if (bits >> 31) {
        out[n++] = '-';
        x = -x;
    } /* also keeps -0 */
    if (x == 0.0) {
        out[n++] = '0';
        return n;
    }
    d = pw__num_digits(x, &e10);
    while (nd > 1 && d % 10 == 0) {
        d /= 10;
        nd--;
    }
    for (i = nd - 1; i >= 0; i--) {
        dig[i] = (char)('0' + d % 10);
        d /= 10;
    }
    if (e10 >= 0 && e10 < 9) { /* ddd.ddd */
        for (i = 0; i <= e10; i++) out[n++] = i < nd ? dig[i] : '0';
        if (nd > e10 + 1) out[n++] = '.';
        for (i = e10 + 1; i < nd; i++) out[n++] = dig[i];
    } else if (e10 < 0 && e10 >= -4) { /* 0.000ddd, as %g does */
        out[n++] = '0';
        out[n++] = '.';
        for (i = 0; i < -e10 - 1; i++) out[n++] = '0';
        for (i = 0; i < nd; i++) out[n++] = dig[i];
    } else { /* d.ddde-12 */
        out[n++] = dig[0];
        if (nd > 1) out[n++] = '.';
        for (i = 1; i < nd; i++) out[n++] = dig[i];
        out[n++] = 'e';
        if (e10 < 0) {
            out[n++] = '-';
            e10 = -e10;
        }
        pos = e10 >= 10 ? 2 : 1;
        for (i = pos - 1; i >= 0; i--, e10 /= 10) out[n + i] = (char)('0' + e10 % 10);
        n += pos;
    }
    return n;
}

PW__DEF void pw__wb_float(pw__wb *b, float x)
{
    char t[24];
    t[0] = ' ';
    pw__wb_put(b, t, (size_t)pw__num_format(t + 1, x) + 1);
}

PW__DEF int pw__wb_done(pw__wb *b, pw_err *e)
{
    pw__wb_flush(b);
    return b->failed ? pw_fail(e, PW_ERR_IO, "write failed") : PW_OK;
}

#endif /* PW__TEXT_V1 */
