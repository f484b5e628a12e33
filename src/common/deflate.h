/* deflate: zlib (RFC 1950) and deflate (RFC 1951) compression and
 * decompression, CRC-32 and Adler-32. PNG needs all of them.
 *
 * Compressor: LZ77 over a 32 KiB window with hash chains (3-byte hash) and
 * one-step lazy matching, then each block of up to 16K symbols is written as
 * whichever of dynamic Huffman, fixed Huffman or stored is smallest. Dynamic
 * codes are canonical and length-limited to 15 bits (7 for the code-length
 * code). Levels 0 (stored only) to 9 (slowest); -1 means the default, 6.
 * The output depends only on the input and the level.
 *
 * Decompressor: stored, fixed and dynamic blocks; every malformed stream is
 * reported (bad block type, over-subscribed or incomplete codes, repeat with
 * no previous length, distance too far back, truncation, bad checksum) and
 * the caller's max_out caps the output so that a small input cannot expand
 * without bound.
 *
 *   pw_crc32(0, data, n), pw_adler32(1, data, n)   checksums (chainable)
 *   pw_deflate / pw_inflate                         raw deflate streams
 *   pw_zlib_compress / pw_zlib_decompress           zlib-wrapped streams
 * Buffers returned in *out come from pw_malloc(a, ...): free with pw_free. */
#ifndef PW__DEFLATE_V1
#define PW__DEFLATE_V1

#include "base.h"

/* CRC-32 as used by PNG and gzip; start with crc = 0. A 16-entry table (one
 * nibble at a time) keeps the source short and is fast enough for PNG. */
PW__DEF uint32_t pw_crc32(uint32_t crc, const void *data, size_t n)
{
    static const uint32_t t[16] = {0x00000000u, 0x1db71064u, 0x3b6e20c8u, 0x26d930acu, 0x76dc4190u, 0x6b6b51f4u,
                                   0x4db26158u, 0x5005713cu, 0xedb88320u, 0xf00f9344u, 0xd6d6a3e8u, 0xcb61b38cu,
                                   0x9b64c2b0u, 0x86d3d2d4u, 0xa00ae278u, 0xbdbdf21cu};
    const unsigned char *p = (const unsigned char *)data;
    crc = ~crc;
    while (n--) {
        crc ^= *p++;
        crc = (crc >> 4) ^ t[crc & 15];
        crc = (crc >> 4) ^ t[crc & 15];
    }
    return ~crc;
}

/* Adler-32 as used by zlib; start with adler = 1. */
PW__DEF uint32_t pw_adler32(uint32_t adler, const void *data, size_t n)
{
    const unsigned char *p = (const unsigned char *)data;
    uint32_t s1 = adler & 0xffff, s2 = adler >> 16;
    while (n > 0) {
        /* 5552 is the largest run for which s2 cannot overflow 32 bits */
        size_t k = n < 5552 ? n : 5552;
        n -= k;
        while (k--) {
            s1 += *p++;
            s2 += s1;
        }
        s1 %= 65521u;
        s2 %= 65521u;
    }
    return (s2 << 16) | s1;
}

/* RFC 1951 §3.2.5: bases and extra bits of the length and distance codes. */
static const unsigned short pw__len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                                31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const unsigned char pw__len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                                2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const unsigned short pw__dist_base[30] = {1,    2,    3,    4,    5,    7,    9,    13,    17,    25,
                                                 33,   49,   65,   97,   129,  193,  257,  385,   513,   769,
                                                 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const unsigned char pw__dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                                 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
/* §3.2.7: order in which the code-length code lengths are sent */
static const unsigned char pw__clen_order[19] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

/* ======================================================================
 * Huffman code construction (shared by both directions)
 * ====================================================================== */

/* Canonical codes from code lengths (§3.2.2), bit-reversed because deflate
 * sends Huffman codes starting from their most significant bit into an
 * LSB-first bit stream. */
PW__DEF void pw__huff_codes(const unsigned char *len, int n, unsigned short *code)
{
    unsigned count[16], next[16], c = 0;
    int i, l;
    memset(count, 0, sizeof count);
    for (i = 0; i < n; i++) count[len[i]]++;
    count[0] = 0;
    for (l = 1; l < 16; l++) {
        c = (c + count[l - 1]) << 1;
        next[l] = c;
    }
    for (i = 0; i < n; i++) {
        unsigned v, r = 0;
        if (!len[i]) continue;
        v = next[len[i]]++;
        for (l = 0; l < len[i]; l++) r = (r << 1) | ((v >> l) & 1u);
        code[i] = (unsigned short)r;
    }
}

/* One Huffman tree over the symbols with nonzero frequency; returns the
 * largest code length. `key` holds freq<<16|symbol, sorted ascending. */
PW__DEF int pw__huff_tree(const uint64_t *key, int m, unsigned char *len)
{
    unsigned w[2 * 288];
    int parent[2 * 288], depth[2 * 288];
    int li = 0, ii = m, nn = m, k, maxd = 0;
    for (k = 0; k < m; k++) w[k] = (unsigned)(key[k] >> 16);
    /* two-queue method: leaves are sorted and internal nodes are created in
     * non-decreasing weight order, so the two smallest are queue heads */
    for (k = 0; k < m - 1; k++) {
        int pick[2], j;
        for (j = 0; j < 2; j++) {
            if (li < m && (ii >= nn || w[li] <= w[ii])) pick[j] = li++;
            else pick[j] = ii++;
        }
        w[nn] = w[pick[0]] + w[pick[1]];
        parent[pick[0]] = parent[pick[1]] = nn++;
    }
    depth[nn - 1] = 0;
    for (k = nn - 2; k >= 0; k--) depth[k] = depth[parent[k]] + 1;
    for (k = 0; k < m; k++) {
        len[key[k] & 0xffff] = (unsigned char)depth[k];
        if (depth[k] > maxd) maxd = depth[k];
    }
    return maxd;
}

/* Code lengths for n <= 288 symbols, none longer than `limit`. When the
 * optimal tree is too deep the frequencies are flattened and the tree
 * rebuilt: rare in practice and costs a fraction of a percent. */
PW__DEF void pw__huff_lengths(const unsigned *freq, int n, int limit, unsigned char *len)
{
    uint64_t key[288];
    unsigned f[288];
    int i, m;
    memset(len, 0, (size_t)n);
    memcpy(f, freq, (size_t)n * sizeof *f);
    for (;;) {
        m = 0;
        for (i = 0; i < n; i++)
            if (f[i]) {
                /* insertion sort by (frequency, symbol): deterministic */
                uint64_t k = ((uint64_t)f[i] << 16) | (unsigned)i;
                int j = m++;
                while (j > 0 && key[j - 1] > k) {
                    key[j] = key[j - 1];
                    j--;
                }
                key[j] = k;
            }
        if (m == 0) return;
        if (m == 1) {
            len[key[0] & 0xffff] = 1;
            return;
        }
        if (pw__huff_tree(key, m, len) <= limit) return;
        for (i = 0; i < n; i++)
            if (f[i]) f[i] = (f[i] >> 1) | 1u;
    }
}

/* ======================================================================
 * Compressor
 * ====================================================================== */

#define PW__WSIZE 32768u
#define PW__WMASK 32767u
#define PW__HASH_BITS 15 /* at most; small inputs use smaller tables */
#define PW__BLOCK_SYMS 16384

typedef struct pw__deflate {
    const pw_alloc *a;
    pw_err *e;
    const unsigned char *in;
    size_t n;
    unsigned char *out; /* output bytes, outn used of outcap */
    size_t outn, outcap;
    uint64_t bitbuf; /* pending output bits, LSB first */
    int bitcount;
    int failed;
    int max_chain, nice_len, max_lazy, good_len, stored_only;
    int hash_bits;         /* 8 to PW__HASH_BITS, by input size */
    size_t wsize;          /* entries of prev: min(n, PW__WSIZE) */
    uint32_t *head, *prev; /* hash chains: head[hash], prev[pos & WMASK]; entries
                            * are pos + WSIZE mod 2^32 (0 = empty; half the
                            * cache footprint of size_t) */
    unsigned short *lit;   /* block symbols: literal byte or match length */
    unsigned short *dist;  /* 0 for a literal */
    size_t nsym, block_start;
    unsigned freq_ll[288], freq_d[30];
    unsigned char lcode[259]; /* match length -> length code 0..28 */
    unsigned char dcode[512]; /* distance code 0..29, see pw__dist_code */
    unsigned char fixed_len[288 + 30];
    unsigned short fixed_code[288 + 30];
} pw__deflate;

/* Makes room for k more output bytes. */
PW__DEF int pw__deflate_reserve(pw__deflate *s, size_t k)
{
    if (s->failed) return -1;
    if (pw_grow(s->a, (void **)&s->out, &s->outcap, s->outn + k, 1, "compressed data", s->e)) {
        s->failed = 1;
        return -1;
    }
    return 0;
}

/* Appends n <= 16 bits; the caller reserved the space. */
PW__DEF void pw__put_bits(pw__deflate *s, unsigned bits, int n)
{
    s->bitbuf |= (uint64_t)bits << s->bitcount;
    s->bitcount += n;
    if (s->bitcount >= 32) {
        unsigned char *o = s->out + s->outn;
        o[0] = (unsigned char)s->bitbuf;
        o[1] = (unsigned char)(s->bitbuf >> 8);
        o[2] = (unsigned char)(s->bitbuf >> 16);
        o[3] = (unsigned char)(s->bitbuf >> 24);
        s->outn += 4;
        s->bitbuf >>= 32;
        s->bitcount -= 32;
    }
}

/* Pads to a byte boundary and writes out every pending bit. */
PW__DEF void pw__flush_bits(pw__deflate *s)
{
    while (s->bitcount > 0) {
        s->out[s->outn++] = (unsigned char)s->bitbuf;
        s->bitbuf >>= 8;
        s->bitcount -= 8;
    }
    s->bitbuf = 0;
    s->bitcount = 0;
}

PW__DEF void pw__deflate_tables(pw__deflate *s)
{
    int c, i;
    for (c = 0; c < 29; c++)
        for (i = 0; i < (1 << pw__len_extra[c]) && pw__len_base[c] + i <= 258; i++)
            s->lcode[pw__len_base[c] + i] = (unsigned char)c;
    s->lcode[258] = 28; /* 258 has its own code, not 227+31 */
    /* distances up to 256 directly, longer ones by 128-wide bands: from
     * code 16 on, each code covers whole bands */
    for (c = 0; c < 30; c++)
        for (i = 0; i<(1 << pw__dist_extra[c]); i += pw__dist_base[c]> 256 ? 128 : 1) {
            int v = pw__dist_base[c] - 1 + i;
            s->dcode[v < 256 ? v : 256 + (v >> 7)] = (unsigned char)c;
        }
    /* §3.2.6: the fixed code */
    for (i = 0; i < 288; i++) s->fixed_len[i] = (unsigned char)(i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8);
    for (i = 0; i < 30; i++) s->fixed_len[288 + i] = 5;
    pw__huff_codes(s->fixed_len, 288, s->fixed_code);
    pw__huff_codes(s->fixed_len + 288, 30, s->fixed_code + 288);
}

PW__DEF int pw__dist_code(const pw__deflate *s, unsigned dist)
{
    return s->dcode[dist <= 256 ? dist - 1 : 256 + ((dist - 1) >> 7)];
}

/* Bits to code the block's symbols with the given lengths (no header). */
PW__DEF uint64_t pw__block_bits(const pw__deflate *s, const unsigned char *ll, const unsigned char *dl)
{
    uint64_t bits = 0;
    int i;
    for (i = 0; i < 286; i++) bits += (uint64_t)s->freq_ll[i] * ll[i];
    for (i = 0; i < 29; i++) bits += (uint64_t)s->freq_ll[257 + i] * pw__len_extra[i];
    for (i = 0; i < 30; i++) bits += (uint64_t)s->freq_d[i] * (dl[i] + pw__dist_extra[i]);
    return bits;
}

/* Writes the block's symbols with the given code. */
PW__DEF void pw__put_symbols(pw__deflate *s, const unsigned char *ll, const unsigned short *lc, const unsigned char *dl,
                             const unsigned short *dc)
{
    size_t i;
    for (i = 0; i < s->nsym; i++) {
        unsigned v = s->lit[i], d = s->dist[i];
        if (!d) {
            pw__put_bits(s, lc[v], ll[v]);
        } else {
            int c = s->lcode[v], x = pw__dist_code(s, d);
            pw__put_bits(s, lc[257 + c], ll[257 + c]);
            if (pw__len_extra[c]) pw__put_bits(s, v - pw__len_base[c], pw__len_extra[c]);
            pw__put_bits(s, dc[x], dl[x]);
            if (pw__dist_extra[x]) pw__put_bits(s, d - pw__dist_base[x], pw__dist_extra[x]);
        }
    }
    pw__put_bits(s, lc[256], ll[256]);
}

/* A dynamic block header (§3.2.7) for the given code lengths. */
typedef struct pw__dyn_header {
    int hlit, hdist, hclen, nrle;
    unsigned char rle_sym[286 + 30], rle_extra[286 + 30];
    unsigned char clen[19];
    unsigned short ccode[19];
} pw__dyn_header;

/* Run-length codes the concatenated length lists with codes 16 (repeat the
 * previous length 3-6 times), 17 (3-10 zeros) and 18 (11-138 zeros). */
PW__DEF void pw__rle_lengths(pw__dyn_header *h, const unsigned char *lens, int n)
{
    int i = 0, k = 0;
    while (i < n) {
        int v = lens[i], run = 1;
        while (i + run < n && lens[i + run] == v) run++;
        if (v == 0 && run >= 3) {
            int r = run > 138 ? 138 : run;
            h->rle_sym[k] = (unsigned char)(r >= 11 ? 18 : 17);
            h->rle_extra[k++] = (unsigned char)(r >= 11 ? r - 11 : r - 3);
            i += r;
        } else if (v != 0 && run >= 4) {
            h->rle_sym[k] = (unsigned char)v;
            h->rle_extra[k++] = 0;
            i++;
            run--;
            while (run >= 3) {
                int r = run > 6 ? 6 : run;
                h->rle_sym[k] = 16;
                h->rle_extra[k++] = (unsigned char)(r - 3);
                i += r;
                run -= r;
            }
        } else {
            h->rle_sym[k] = (unsigned char)v;
            h->rle_extra[k++] = 0;
            i++;
        }
    }
    h->nrle = k;
}

/* Builds the header for lengths ll[286], dl[30]; returns its size in bits. */
PW__DEF uint64_t pw__dyn_build(pw__dyn_header *h, const unsigned char *ll, const unsigned char *dl)
{
    unsigned char lens[286 + 30];
    unsigned cfreq[19];
    uint64_t bits;
    int i, used;
    h->hlit = 286;
    while (h->hlit > 257 && !ll[h->hlit - 1]) h->hlit--;
    h->hdist = 30;
    while (h->hdist > 1 && !dl[h->hdist - 1]) h->hdist--;
    memcpy(lens, ll, (size_t)h->hlit);
    memcpy(lens + h->hlit, dl, (size_t)h->hdist);
    pw__rle_lengths(h, lens, h->hlit + h->hdist);
    memset(cfreq, 0, sizeof cfreq);
    for (i = 0; i < h->nrle; i++) cfreq[h->rle_sym[i]]++;
    /* decoders reject a code-length code with a single code; a dummy
     * second one costs nothing since it is never sent */
    for (i = 0, used = 0; i < 19; i++) used += cfreq[i] != 0;
    if (used < 2) cfreq[cfreq[0] ? 1 : 0]++;
    pw__huff_lengths(cfreq, 19, 7, h->clen);
    pw__huff_codes(h->clen, 19, h->ccode);
    h->hclen = 19;
    while (h->hclen > 4 && !h->clen[pw__clen_order[h->hclen - 1]]) h->hclen--;
    bits = 5 + 5 + 4 + 3 * (uint64_t)h->hclen;
    for (i = 0; i < 19; i++) bits += (uint64_t)cfreq[i] * h->clen[i];
    bits += 2 * (uint64_t)cfreq[16] + 3 * (uint64_t)cfreq[17] + 7 * (uint64_t)cfreq[18];
    return bits;
}

PW__DEF void pw__dyn_put(pw__deflate *s, const pw__dyn_header *h)
{
    static const unsigned char xbits[3] = {2, 3, 7};
    int i;
    pw__put_bits(s, (unsigned)(h->hlit - 257), 5);
    pw__put_bits(s, (unsigned)(h->hdist - 1), 5);
    pw__put_bits(s, (unsigned)(h->hclen - 4), 4);
    for (i = 0; i < h->hclen; i++) pw__put_bits(s, h->clen[pw__clen_order[i]], 3);
    for (i = 0; i < h->nrle; i++) {
        int v = h->rle_sym[i];
        pw__put_bits(s, h->ccode[v], h->clen[v]);
        if (v >= 16) pw__put_bits(s, h->rle_extra[i], xbits[v - 16]);
    }
}

/* Stored blocks for in[start, end), split at 65535 bytes. */
PW__DEF void pw__put_stored(pw__deflate *s, size_t start, size_t end, int last)
{
    do {
        size_t k = end - start > 65535 ? 65535 : end - start;
        pw__put_bits(s, (unsigned)(last && start + k == end), 1);
        pw__put_bits(s, 0, 2);
        pw__flush_bits(s);
        s->out[s->outn++] = (unsigned char)k;
        s->out[s->outn++] = (unsigned char)(k >> 8);
        s->out[s->outn++] = (unsigned char)~k;
        s->out[s->outn++] = (unsigned char)(~k >> 8);
        if (k) memcpy(s->out + s->outn, s->in + start, k);
        s->outn += k;
        start += k;
    } while (start < end);
}

/* Ends the current block at input position `end`, choosing the cheapest of
 * dynamic, fixed and stored coding. */
PW__DEF void pw__flush_block(pw__deflate *s, size_t end, int last)
{
    unsigned fll[288], fd[30];
    unsigned char ll[288], dl[30];
    unsigned short lc[288], dc[30];
    pw__dyn_header h;
    uint64_t dyn, fix, raw = (uint64_t)(end - s->block_start);
    uint64_t stored = 8 * (raw + 5 * (raw / 65535 + 1)) + 10;
    int i, nd = 0, kind;
    s->freq_ll[256] = 1;
    /* at least two codes per tree: some decoders reject a one-code tree */
    memcpy(fll, s->freq_ll, sizeof fll);
    memcpy(fd, s->freq_d, sizeof fd);
    if (s->nsym == 0) fll[0] = 1;
    for (i = 0; i < 30; i++) nd += fd[i] != 0;
    if (nd < 2) fd[0] = fd[1] = 1;
    pw__huff_lengths(fll, 286, 15, ll);
    ll[286] = ll[287] = 0;
    pw__huff_lengths(fd, 30, 15, dl);
    dyn = 3 + pw__dyn_build(&h, ll, dl) + pw__block_bits(s, ll, dl);
    fix = 3 + pw__block_bits(s, s->fixed_len, s->fixed_len + 288);
    kind = s->stored_only || (stored <= dyn && stored <= fix) ? 0 : fix <= dyn ? 1 : 2;
    if (pw__deflate_reserve(s, (size_t)((kind == 0 ? stored : kind == 1 ? fix : dyn) / 8 + 16))) return;
    if (kind == 0) {
        pw__put_stored(s, s->block_start, end, last);
    } else if (kind == 1) {
        pw__put_bits(s, (unsigned)last | 2u, 3); /* BTYPE 01, LSB first */
        pw__put_symbols(s, s->fixed_len, s->fixed_code, s->fixed_len + 288, s->fixed_code + 288);
    } else {
        pw__huff_codes(ll, 288, lc);
        pw__huff_codes(dl, 30, dc);
        pw__put_bits(s, (unsigned)last | 4u, 3); /* BTYPE 10 */
        pw__dyn_put(s, &h);
        pw__put_symbols(s, ll, lc, dl, dc);
    }
    s->nsym = 0;
    s->block_start = end;
    memset(s->freq_ll, 0, sizeof s->freq_ll);
    memset(s->freq_d, 0, sizeof s->freq_d);
}

/* Multiplicative hash of the 3 bytes at p. */
PW__DEF unsigned pw__hash3(const unsigned char *p, int bits)
{
    uint32_t v = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16);
    return (unsigned)((v * 2654435761u) >> (32 - bits));
}

PW__DEF void pw__insert(pw__deflate *s, size_t pos)
{
    unsigned h;
    if (pos + 2 >= s->n) return;
    h = pw__hash3(s->in + pos, s->hash_bits);
    s->prev[pos & PW__WMASK] = s->head[h];
    s->head[h] = (uint32_t)pos + PW__WSIZE;
}

/* Longest match for the bytes at pos among earlier positions in the window;
 * returns its length (0 if under 3) and sets *dist. A chain entry within the
 * window is never stale, because a slot is only reused by a position 32K
 * later. Positions are stored mod 2^32: past 4 GiB an old entry may alias a
 * recent one, which only costs a wasted comparison, since every candidate
 * is checked byte by byte. */
PW__DEF size_t pw__longest_match(const pw__deflate *s, size_t pos, size_t prev_len, size_t *dist)
{
    const unsigned char *in = s->in, *cur = in + pos;
    const uint32_t *prev = s->prev;
    size_t maxlen = s->n - pos, best = 2, cand, l;
    uint32_t c32, d;
    /* when deferring a good match, a shorter search for a better one */
    int chain = prev_len && prev_len >= (size_t)s->good_len ? s->max_chain >> 2 : s->max_chain;
    unsigned char end0, end1;
    if (maxlen < 3 || chain <= 0) return 0;
    if (maxlen > 258) maxlen = 258;
    end0 = cur[1];
    end1 = cur[2];
    for (c32 = s->head[pw__hash3(cur, s->hash_bits)]; chain-- > 0; c32 = prev[cand & PW__WMASK]) {
        const unsigned char *m;
        d = (uint32_t)pos + PW__WSIZE - c32; /* the distance back */
        if (d == 0 || d >= PW__WSIZE || d > pos) break;
        cand = pos - d;
        m = in + cand;
        /* the two bytes that would make this match longer decide first */
        if (m[best] != end1 || m[best - 1] != end0 || m[0] != cur[0] || m[1] != cur[1]) continue;
        for (l = 2; l < maxlen && m[l] == cur[l];) l++;
        if (l > best) {
            best = l;
            *dist = pos - cand;
            if (l >= (size_t)s->nice_len || l >= maxlen) break;
            end0 = cur[best - 1];
            end1 = cur[best];
        }
    }
    /* a far 3-byte match usually costs more bits than three literals */
    if (best < 3 || (best == 3 && *dist > 4096)) return 0;
    return best;
}

PW__DEF void pw__emit(pw__deflate *s, unsigned lit_or_len, unsigned dist)
{
    s->lit[s->nsym] = (unsigned short)lit_or_len;
    s->dist[s->nsym++] = (unsigned short)dist;
    if (!dist) {
        s->freq_ll[lit_or_len]++;
    } else {
        s->freq_ll[257 + s->lcode[lit_or_len]]++;
        s->freq_d[pw__dist_code(s, dist)]++;
    }
}

/* LZ77 with one-step lazy evaluation: a match is deferred while the next
 * position offers a longer one. */
PW__DEF void pw__deflate_run(pw__deflate *s)
{
    size_t pos = 0, n = s->n, len, dist = 0, k;
    while (pos < n && !s->failed) {
        /* room for up to 257 deferred literals plus one match */
        if (s->nsym >= PW__BLOCK_SYMS - 260) pw__flush_block(s, pos, 0);
        len = pw__longest_match(s, pos, 0, &dist);
        pw__insert(s, pos);
        while (len && len < (size_t)s->max_lazy && pos + 1 < n) {
            size_t d2 = 0, l2 = pw__longest_match(s, pos + 1, len, &d2);
            if (l2 <= len) break;
            pw__emit(s, s->in[pos], 0);
            pos++;
            pw__insert(s, pos);
            len = l2;
            dist = d2;
        }
        if (len) {
            pw__emit(s, (unsigned)len, (unsigned)dist);
            for (k = 1; k < len; k++) pw__insert(s, pos + k);
            pos += len;
        } else {
            pw__emit(s, s->in[pos], 0);
            pos++;
        }
    }
    if (!s->failed) pw__flush_block(s, n, 1);
}

/* Search effort per level: hash chain length, "nice" length at which the
 * search stops, the length under which lazy matching is tried, and the
 * length of a deferred match above which the lazy search is shortened. */
PW__DEF void pw__deflate_level(pw__deflate *s, int level)
{
    static const unsigned short p[10][4] = {
        {0, 0, 0, 0},    {4, 16, 0, 0},    {8, 32, 0, 0},      {16, 32, 0, 0},       {16, 32, 8, 4},
        {32, 64, 16, 8}, {64, 128, 16, 8}, {256, 128, 64, 16}, {1024, 258, 128, 32}, {4096, 258, 258, 32}};
    if (level < 0 || level > 9) level = 6;
    s->max_chain = p[level][0];
    s->nice_len = p[level][1];
    s->max_lazy = p[level][2];
    s->good_len = p[level][3];
    s->stored_only = level == 0;
}

PW__DEF void pw__deflate_free(pw__deflate *s)
{
    pw_free(s->a, s->head);
    pw_free(s->a, s->prev);
    pw_free(s->a, s->lit);
    pw_free(s->a, s->dist);
}

/* Compresses into s->out after whatever is already there. */
PW__DEF int pw__deflate_into(pw__deflate *s, int level)
{
    size_t nsyms;
    pw__deflate_level(s, level);
    /* small inputs need small tables: positions below n index prev
     * directly when n <= WSIZE */
    s->hash_bits = 8;
    while (s->hash_bits < PW__HASH_BITS && ((size_t)1 << s->hash_bits) < s->n) s->hash_bits++;
    s->wsize = s->n < PW__WSIZE ? (s->n ? s->n : 1) : PW__WSIZE;
    s->head = (uint32_t *)pw_alloc_array(s->a, (size_t)1 << s->hash_bits, 4, "deflate hash", s->e);
    s->prev = (uint32_t *)pw_alloc_array(s->a, s->wsize, 4, "deflate window", s->e);
    /* every symbol covers at least one input byte */
    nsyms = s->n < PW__BLOCK_SYMS ? s->n + 1 : PW__BLOCK_SYMS;
    s->lit = (unsigned short *)pw_alloc_array(s->a, nsyms, 2, "deflate symbols", s->e);
    s->dist = (unsigned short *)pw_alloc_array(s->a, nsyms, 2, "deflate symbols", s->e);
    if (!s->head || !s->prev || !s->lit || !s->dist) {
        pw__deflate_free(s);
        return PW_ERR_NOMEM;
    }
    /* empty entries (0) lie a whole window back: the distance check ends
     * every chain there */
    memset(s->head, 0, sizeof(uint32_t) << s->hash_bits);
    memset(s->prev, 0, sizeof(uint32_t) * s->wsize);
    pw__deflate_tables(s);
    pw__deflate_run(s);
    pw__deflate_free(s);
    if (!s->failed && pw__deflate_reserve(s, 8) == 0) pw__flush_bits(s);
    return s->failed ? (s->e && s->e->code ? s->e->code : PW_ERR_NOMEM) : PW_OK;
}

PW__DEF void pw__deflate_init(pw__deflate *s, const pw_alloc *a, const unsigned char *data, size_t n, pw_err *e)
{
    memset(s, 0, sizeof *s);
    s->a = a;
    s->e = e;
    s->in = data;
    s->n = n;
}

/* Raw deflate stream of data[0..n) at `level` (0-9, -1 = default 6). */
PW__DEF int pw_deflate(const pw_alloc *a, const unsigned char *data, size_t n, int level, unsigned char **out,
                       size_t *outn, pw_err *e)
{
    pw__deflate s;
    int r;
    *out = NULL;
    *outn = 0;
    pw__deflate_init(&s, a, data, n, e);
    r = pw__deflate_into(&s, level);
    if (r) {
        pw_free(a, s.out);
        return r;
    }
    *out = s.out;
    *outn = s.outn;
    return PW_OK;
}

/* zlib stream (2-byte header, deflate data, Adler-32 of the input). */
PW__DEF int pw_zlib_compress(const pw_alloc *a, const unsigned char *data, size_t n, int level, unsigned char **out,
                             size_t *outn, pw_err *e)
{
    pw__deflate s;
    uint32_t ad;
    unsigned flg;
    int r;
    *out = NULL;
    *outn = 0;
    if (level < 0 || level > 9) level = 6;
    pw__deflate_init(&s, a, data, n, e);
    if (pw__deflate_reserve(&s, 2)) return e && e->code ? e->code : PW_ERR_NOMEM;
    /* CMF: deflate with a 32K window; FLG: level hint, then FCHECK makes
     * CMF*256+FLG a multiple of 31 */
    flg = (unsigned)(level <= 1 ? 0 : level <= 5 ? 1 : level == 6 ? 2 : 3) << 6;
    flg += (31 - (0x7800u + flg) % 31) % 31;
    s.out[0] = 0x78;
    s.out[1] = (unsigned char)flg;
    s.outn = 2;
    r = pw__deflate_into(&s, level);
    if (!r && pw__deflate_reserve(&s, 4)) r = e && e->code ? e->code : PW_ERR_NOMEM;
    if (r) {
        pw_free(a, s.out);
        return r;
    }
    ad = pw_adler32(1, data, n);
    s.out[s.outn++] = (unsigned char)(ad >> 24);
    s.out[s.outn++] = (unsigned char)(ad >> 16);
    s.out[s.outn++] = (unsigned char)(ad >> 8);
    s.out[s.outn++] = (unsigned char)ad;
    *out = s.out;
    *outn = s.outn;
    return PW_OK;
}

/* ======================================================================
 * Decompressor
 * ====================================================================== */

#define PW__FAST_BITS 9

/* A decoding table: codes up to FAST_BITS long are looked up directly
 * (entry = length << 9 | symbol, 0 = longer code); longer ones are decoded
 * bit by bit from the canonical counts (§3.2.2). */
typedef struct pw__huff {
    unsigned short fast[1 << PW__FAST_BITS];
    unsigned short count[16];
    unsigned short sym[288];
    int maxlen; /* longest code */
} pw__huff;

/* Returns 0, or -1 for an over-subscribed set, -2 for an incomplete one.
 * Incomplete sets are allowed (for literal/length and distance codes) only
 * when they have at most one code, as zlib does: an encoder may send a
 * single distance code, or none for an all-literal block. */
PW__DEF int pw__huff_build(pw__huff *h, const unsigned char *len, int n, int allow_one)
{
    unsigned short offs[16], code[16];
    int i, l, left = 1, ncodes = 0;
    unsigned short c = 0;
    memset(h, 0, sizeof *h);
    for (i = 0; i < n; i++) h->count[len[i]]++;
    h->count[0] = 0;
    for (l = 1; l < 16; l++) {
        left = (left << 1) - h->count[l];
        if (left < 0) return -1;
        ncodes += h->count[l];
        if (h->count[l]) h->maxlen = l;
    }
    if (left > 0 && !(allow_one && ncodes <= 1)) return -2;
    offs[1] = 0;
    for (l = 1; l < 15; l++) offs[l + 1] = (unsigned short)(offs[l] + h->count[l]);
    for (l = 1; l < 16; l++) {
        code[l] = c;
        c = (unsigned short)((c + h->count[l]) << 1);
    }
    for (i = 0; i < n; i++) {
        int L = len[i];
        unsigned r = 0, j;
        if (!L) continue;
        h->sym[offs[L]++] = (unsigned short)i;
        if (L > PW__FAST_BITS) continue;
        for (l = 0; l < L; l++) r = (r << 1) | ((code[L] >> l) & 1u);
        code[L]++;
        for (j = r; j < (1u << PW__FAST_BITS); j += 1u << L) h->fast[j] = (unsigned short)((L << 9) | i);
    }
    return 0;
}

typedef struct pw__inflate {
    const unsigned char *in;
    size_t n, pos; /* input and the next byte to load */
    uint64_t bits; /* loaded bits, LSB first */
    int nbits;
    int truncated; /* a read went past the end of the input */
    unsigned char *out;
    size_t outn, outcap, max_out;
    const pw_alloc *a;
    pw_err *e;
} pw__inflate;

PW__DEF void pw__refill(pw__inflate *z)
{
    while (z->nbits <= 56 && z->pos < z->n) {
        z->bits |= (uint64_t)z->in[z->pos++] << z->nbits;
        z->nbits += 8;
    }
}

/* Reads n <= 16 bits; past the end, sets z->truncated and returns 0. */
PW__DEF unsigned pw__getbits(pw__inflate *z, int n)
{
    unsigned v;
    if (z->nbits < n) pw__refill(z);
    if (z->nbits < n) {
        z->truncated = 1;
        return 0;
    }
    v = (unsigned)(z->bits & ((1u << n) - 1));
    z->bits >>= n;
    z->nbits -= n;
    return v;
}

/* Decodes one symbol: -1 when the input ends, -2 for an unused code. */
PW__DEF int pw__decode(pw__inflate *z, const pw__huff *h)
{
    int l, code = 0, first = 0, index = 0;
    unsigned e;
    if (z->nbits < 15) pw__refill(z);
    e = h->fast[z->bits & ((1u << PW__FAST_BITS) - 1)];
    if (e) {
        l = (int)(e >> 9);
        if (l > z->nbits) return -1;
        z->bits >>= l;
        z->nbits -= l;
        return (int)(e & 511);
    }
    for (l = 1; l <= h->maxlen; l++) {
        if (l > z->nbits) return -1;
        code |= (int)((z->bits >> (l - 1)) & 1);
        if (code - first < h->count[l]) {
            z->bits >>= l;
            z->nbits -= l;
            return h->sym[index + code - first];
        }
        index += h->count[l];
        first = (first + h->count[l]) << 1;
        code <<= 1;
    }
    return -2;
}

PW__DEF int pw__inflate_truncated(pw__inflate *z)
{
    return pw_fail(z->e, PW_ERR_PARSE, "deflate data truncated (ends mid-block)");
}

/* Makes room for k more output bytes, within max_out. */
PW__DEF int pw__inflate_reserve(pw__inflate *z, size_t k)
{
    size_t need = z->outn + k, cap;
    unsigned char *p;
    if (need <= z->outcap) return PW_OK;
    if (k > z->max_out || z->outn > z->max_out - k)
        return pw_fail(z->e, PW_ERR_LIMIT, "deflate data expands beyond the limit of %lu bytes",
                       (unsigned long)z->max_out);
    cap = z->outcap ? z->outcap : 4096;
    while (cap < need) cap = cap > ((size_t)-1) / 2 ? need : cap * 2;
    if (cap > z->max_out) cap = z->max_out;
    p = (unsigned char *)pw_realloc(z->a, z->out, cap);
    if (!p) return pw_fail(z->e, PW_ERR_NOMEM, "out of memory decompressing (%lu bytes)", (unsigned long)cap);
    z->out = p;
    z->outcap = cap;
    return PW_OK;
}

/* Decodes symbols until end-of-block with the given codes (§3.2.5). */
PW__DEF int pw__inflate_codes(pw__inflate *z, const pw__huff *ll, const pw__huff *dd)
{
    int sym, ds;
    size_t len, dist, i;
    for (;;) {
        sym = pw__decode(z, ll);
        if (sym < 0) goto bad;
        if (sym < 256) {
            if (z->outn >= z->outcap && pw__inflate_reserve(z, 1)) return z->e ? z->e->code : PW_ERR_LIMIT;
            z->out[z->outn++] = (unsigned char)sym;
            continue;
        }
        if (sym == 256) return PW_OK;
        if (sym > 285) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: invalid length code %d", sym);
        len = pw__len_base[sym - 257] + pw__getbits(z, pw__len_extra[sym - 257]);
        ds = pw__decode(z, dd);
        if (ds < 0) {
            sym = ds;
            goto bad;
        }
        if (ds > 29) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: invalid distance code %d", ds);
        dist = pw__dist_base[ds] + pw__getbits(z, pw__dist_extra[ds]);
        if (z->truncated) return pw__inflate_truncated(z);
        if (dist > z->outn)
            return pw_fail(z->e, PW_ERR_PARSE, "deflate data: distance %lu too far back (only %lu bytes decoded)",
                           (unsigned long)dist, (unsigned long)z->outn);
        if (pw__inflate_reserve(z, len)) return z->e ? z->e->code : PW_ERR_LIMIT;
        /* byte by byte: source and destination overlap when dist < len */
        for (i = 0; i < len; i++, z->outn++) z->out[z->outn] = z->out[z->outn - dist];
    }
bad:
    if (sym == -1) return pw__inflate_truncated(z);
    return pw_fail(z->e, PW_ERR_PARSE, "deflate data: invalid Huffman code");
}

PW__DEF int pw__inflate_stored(pw__inflate *z)
{
    unsigned len, nlen;
    z->bits >>= z->nbits & 7; /* skip to a byte boundary */
    z->nbits -= z->nbits & 7;
    len = pw__getbits(z, 16);
    nlen = pw__getbits(z, 16);
    if (z->truncated) return pw__inflate_truncated(z);
    if ((len ^ 0xffffu) != nlen) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: stored block length check failed");
    if (pw__inflate_reserve(z, len)) return z->e ? z->e->code : PW_ERR_LIMIT;
    while (len > 0 && z->nbits >= 8) { /* bytes already loaded first */
        z->out[z->outn++] = (unsigned char)pw__getbits(z, 8);
        len--;
    }
    if (len > z->n - z->pos) return pw__inflate_truncated(z);
    if (len) memcpy(z->out + z->outn, z->in + z->pos, len);
    z->outn += len;
    z->pos += len;
    return PW_OK;
}

/* Reads the code lengths of a dynamic block and builds its codes (§3.2.7). */
PW__DEF int pw__inflate_tables(pw__inflate *z, pw__huff *ll, pw__huff *dd)
{
    unsigned char lens[286 + 30], clen[19];
    pw__huff ch;
    int hlit, hdist, hclen, i = 0, n;
    hlit = (int)pw__getbits(z, 5) + 257;
    hdist = (int)pw__getbits(z, 5) + 1;
    hclen = (int)pw__getbits(z, 4) + 4;
    if (hlit > 286 || hdist > 30)
        return pw_fail(z->e, PW_ERR_PARSE, "deflate data: too many length or distance codes (%d, %d)", hlit, hdist);
    memset(clen, 0, sizeof clen);
    for (i = 0; i < hclen; i++) clen[pw__clen_order[i]] = (unsigned char)pw__getbits(z, 3);
    if (z->truncated) return pw__inflate_truncated(z);
    if (pw__huff_build(&ch, clen, 19, 0)) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: bad code-length code");
    n = hlit + hdist;
    for (i = 0; i < n;) {
        int sym = pw__decode(z, &ch), rep, val = 0;
        if (sym < 0)
            return sym == -1 ? pw__inflate_truncated(z)
                             : pw_fail(z->e, PW_ERR_PARSE, "deflate data: invalid code-length code");
        if (sym < 16) {
            lens[i++] = (unsigned char)sym;
            continue;
        }
        if (sym == 16) {
            if (i == 0) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: length repeat with no previous length");
            val = lens[i - 1];
            rep = 3 + (int)pw__getbits(z, 2);
        } else {
            rep = sym == 17 ? 3 + (int)pw__getbits(z, 3) : 11 + (int)pw__getbits(z, 7);
        }
        if (z->truncated) return pw__inflate_truncated(z);
        if (rep > n - i) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: code lengths repeat past the end");
        while (rep--) lens[i++] = (unsigned char)val;
    }
    if (!lens[256]) return pw_fail(z->e, PW_ERR_PARSE, "deflate data: no end-of-block code");
    if (pw__huff_build(ll, lens, hlit, 1))
        return pw_fail(z->e, PW_ERR_PARSE, "deflate data: bad literal/length code lengths");
    if (pw__huff_build(dd, lens + hlit, hdist, 1))
        return pw_fail(z->e, PW_ERR_PARSE, "deflate data: bad distance code lengths");
    return PW_OK;
}

/* Decodes every block up to the final one. */
PW__DEF int pw__inflate_run(pw__inflate *z)
{
    pw__huff ll, dd;
    unsigned char lens[288 + 32];
    int last, type, r, i;
    do {
        last = (int)pw__getbits(z, 1);
        type = (int)pw__getbits(z, 2);
        if (z->truncated) return pw__inflate_truncated(z);
        if (type == 0) {
            r = pw__inflate_stored(z);
        } else if (type == 1) { /* §3.2.6: the fixed code */
            for (i = 0; i < 288; i++) lens[i] = (unsigned char)(i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8);
            /* distance codes 30 and 31 never occur but complete the code */
            for (i = 0; i < 32; i++) lens[288 + i] = 5;
            pw__huff_build(&ll, lens, 288, 0);
            pw__huff_build(&dd, lens + 288, 32, 0);
            r = pw__inflate_codes(z, &ll, &dd);
        } else if (type == 2) {
            r = pw__inflate_tables(z, &ll, &dd);
            if (!r) r = pw__inflate_codes(z, &ll, &dd);
        } else {
            r = pw_fail(z->e, PW_ERR_PARSE, "deflate data: invalid block type 3");
        }
        if (r) return r;
    } while (!last);
    return PW_OK;
}

/* Decodes a raw deflate stream into a new buffer of at most max_out bytes
 * (PW_ERR_LIMIT beyond). *used (if not NULL) receives the number of input
 * bytes the stream occupied. */
PW__DEF int pw_inflate(const pw_alloc *a, const unsigned char *data, size_t n, size_t max_out, unsigned char **out,
                       size_t *outn, size_t *used, pw_err *e)
{
    pw__inflate z;
    pw_err local;
    int r;
    *out = NULL;
    *outn = 0;
    memset(&z, 0, sizeof z);
    z.in = data;
    z.n = n;
    z.max_out = max_out;
    z.a = a;
    z.e = e ? e : &local;
    pw_err_clear(&local);
    r = pw__inflate_run(&z);
    if (r) {
        pw_free(a, z.out);
        return r;
    }
    if (!z.out && !(z.out = (unsigned char *)pw_malloc(a, 1)))
        return pw_fail(e, PW_ERR_NOMEM, "out of memory decompressing");
    if (used) *used = z.pos - (size_t)(z.nbits / 8);
    *out = z.out;
    *outn = z.outn;
    return PW_OK;
}

/* Decodes a zlib stream, checking its header and Adler-32. */
PW__DEF int pw_zlib_decompress(const pw_alloc *a, const unsigned char *data, size_t n, size_t max_out,
                               unsigned char **out, size_t *outn, pw_err *e)
{
    size_t used = 0;
    uint32_t want;
    const unsigned char *t;
    int r;
    *out = NULL;
    *outn = 0;
    if (n < 2) return pw_fail(e, PW_ERR_PARSE, "zlib data truncated (%lu bytes)", (unsigned long)n);
    if ((data[0] & 15) != 8 || (data[0] >> 4) > 7)
        return pw_fail(e, PW_ERR_PARSE, "zlib header: not deflate with a window of at most 32K (0x%02x)", data[0]);
    if (((unsigned)data[0] << 8 | data[1]) % 31) return pw_fail(e, PW_ERR_PARSE, "zlib header: check bits are wrong");
    if (data[1] & 0x20) return pw_fail(e, PW_ERR_UNSUPPORTED, "zlib data needs a preset dictionary");
    r = pw_inflate(a, data + 2, n - 2, max_out, out, outn, &used, e);
    if (r) return r;
    t = data + 2 + used;
    if (n - 2 - used < 4) r = pw_fail(e, PW_ERR_PARSE, "zlib data truncated (no Adler-32 checksum)");
    want = r ? 0 : (uint32_t)t[0] << 24 | (uint32_t)t[1] << 16 | (uint32_t)t[2] << 8 | t[3];
    if (!r && pw_adler32(1, *out, *outn) != want) r = pw_fail(e, PW_ERR_PARSE, "zlib data: Adler-32 checksum mismatch");
    if (r) {
        pw_free(a, *out);
        *out = NULL;
        *outn = 0;
    }
    return r;
}

#endif /* PW__DEFLATE_V1 */
