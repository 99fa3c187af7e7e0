/* Exact, locale-independent decimal number parsing for the BVH reader's hot loop.
 *
 * Most BVH numbers have at most 19 significant digits and a small exponent: the digits then fit
 * a uint64_t mantissa m and, when m <= 2^53 and |exp10| <= 22, both m and 10^|exp10| are exact
 * doubles, so one IEEE multiplication or division gives the correctly rounded result (Clinger's
 * fast path). Everything else goes to rf_bvh_parse_slow, which hands strtod a rewritten token. */
#ifndef RIGFLOW_PLUGINS_BVH_NUM_H
#define RIGFLOW_PLUGINS_BVH_NUM_H

#include <float.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/* The slow path for the token [s, end) already checked by bvh_number: exact via strtod. */
const char *rf_bvh_parse_slow(const char *s, const char *end, double *out);

/* The fast path is exact only when double arithmetic is not carried out in wider registers. */
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0
#define BVH_FAST_PATH 1
#else
#define BVH_FAST_PATH 0

#endif

/* The number parsers are called from a few places; inlining them into the per-frame loop lets
 * the processor overlap consecutive numbers. */
#if defined(__GNUC__)
#define BVH_INLINE static inline __attribute__((always_inline))
#else
#define BVH_INLINE static inline
#endif

static inline bool bvh_is_digit(char c)
{
    return (unsigned)(c - '0') < 10u;
}

/* See rf_bvh_parse_double in bvh.h. */
static inline const char *bvh_number(const char *s, double *out)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *p = s;
    bool neg = *p == '-';
    if (*p == '-' || *p == '+')
        p++;
    uint64_t m = 0;
    int digits = 0, exp10 = 0;
    bool any = false, dropped = false;
    /* Leading zeros are not significant; once m is non-zero every digit is. */
    for (; bvh_is_digit(*p); p++, any = true) {
        unsigned d = (unsigned)(*p - '0');
        if (digits < 19 && (m || d))
            m = m * 10 + d, digits++;
        else if (m || d)
            dropped = true, exp10++;
    }
    if (*p == '.') {
        for (p++; bvh_is_digit(*p); p++, any = true) {
            unsigned d = (unsigned)(*p - '0');
            if (digits < 19 && (m || d))
                m = m * 10 + d, digits++, exp10--;
            else if (m || d)
                dropped = true;
            else
                exp10--;
        }
    }
    if (!any)
        return 0;
    if (*p == 'e' || *p == 'E') {
        const char *q = p + 1;
        bool eneg = *q == '-';
        if (*q == '-' || *q == '+')
            q++;
        if (!bvh_is_digit(*q))
            return 0;
        int e = 0;
        for (; bvh_is_digit(*q); q++)
            if (e < 100000000)
                e = e * 10 + (*q - '0');
        exp10 += eneg ? -e : e;
        p = q;
    }
    if (BVH_FAST_PATH && !dropped && m <= (UINT64_C(1) << 53)) {
        double v = (double)m;
        if (m == 0) {
            *out = neg ? -0.0 : 0.0;
            return p;
        }
        if (exp10 >= -22 && exp10 <= 22) {
            v = exp10 < 0 ? v / pow10[-exp10] : v * pow10[exp10];
            *out = neg ? -v : v;
            return p;
        }
    }
    return rf_bvh_parse_slow(s, p, out);
}

#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define BVH_SWAR 1
#else
#define BVH_SWAR 0
#endif

/* Bytes readable past the end of the text handed to bvh_number_padded. */
#define BVH_PAD 32

#if BVH_SWAR
/* The value of up to 8 decimal digits held one per byte (0..9, the first digit in the lowest
 * byte, leading bytes 0): adjacent digits pair into 2-digit lanes, then 4, then 8. Each step
 * stays inside its lane, so one 64-bit multiply does all lanes. */
static inline uint64_t bvh_swar8(uint64_t d)
{
    d = ((d * 10) + (d >> 8)) & 0x00FF00FF00FF00FFull;
    d = ((d * 100) + (d >> 16)) & 0x0000FFFF0000FFFFull;
    return ((d * 10000) + (d >> 32)) & 0xFFFFFFFFull;
}

/* The number of leading decimal digits among the 8 bytes at p (8 when all are), and their
 * values per byte in *digits. A byte below '0' borrows from the next byte up, but only bytes
 * after the first non-digit are affected, and those are not counted. */
static inline unsigned bvh_digits8(const char *p, uint64_t *digits)
{
    uint64_t w;
    memcpy(&w, p, 8);
    uint64_t d = w - 0x3030303030303030ull;
    uint64_t nondigit = (d | (w + 0x4646464646464646ull)) & 0x8080808080808080ull;
    *digits = d;
    return nondigit ? (unsigned)__builtin_ctzll(nondigit) >> 3 : 8;
}

/* The value of the first n (1..7) digits from bvh_digits8. */
static inline uint64_t bvh_digits_value(uint64_t digits, unsigned n)
{
    return bvh_swar8(digits << (64 - 8 * n));
}
#endif

/* bvh_number for text with BVH_PAD readable bytes after its end: the common shape
 * [-]d{0,7}[.d{0,7}][e[+-]d+] is read 8 bytes at a time; anything else goes to bvh_number. */
BVH_INLINE const char *bvh_number_padded(const char *s, double *out)
{
#if BVH_SWAR && BVH_FAST_PATH
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    static const uint64_t ipow10[8] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000};
    const char *p = s + (*s == '-');
    uint64_t digits, m = 0;
    unsigned ni = bvh_digits8(p, &digits), nf = 0;
    if (ni == 8)
        return bvh_number(s, out);
    if (ni)
        m = bvh_digits_value(digits, ni);
    p += ni;
    if (*p == '.') {
        nf = bvh_digits8(++p, &digits);
        if (nf == 8)
            return bvh_number(s, out);
        if (nf)
            m = m * ipow10[nf] + bvh_digits_value(digits, nf);
        p += nf;
    }
    if (ni + nf == 0)
        return bvh_number(s, out);
    int x = -(int)nf;             /* the decimal exponent */
    if (*p == 'e' || *p == 'E') { /* exporters write small values so: 8.68687e-06 */
        const char *q = p + 1 + (p[1] == '-' || p[1] == '+');
        int e = 0;
        for (; bvh_is_digit(*q) && e < 1000; q++)
            e = e * 10 + (*q - '0');
        if (!bvh_is_digit(q[-1]) || bvh_is_digit(*q))
            return bvh_number(s, out); /* no exponent digits, or a huge exponent */
        x += p[1] == '-' ? -e : e;
        if (x < -22 || x > 22)
            return bvh_number(s, out);
        p = q;
    }
    /* at most 14 digits: m < 2^53 and 10^|x| exact, so one operation rounds correctly */
    double v = x < 0 ? (double)m / pow10[-x] : (double)m * pow10[x];
    *out = *s == '-' ? -v : v;
    return p;
#else
    return bvh_number(s, out);
#endif
}

#if BVH_SWAR && BVH_FAST_PATH && defined(__SSE2__)
#include <emmintrin.h>
#define BVH_TOKEN 1

/* A number of at most 8 digits, with an optional '-' and '.', that ends within 16 bytes at a
 * space, tab, CR or LF (BVH_PAD readable bytes after the text): its value, its end, and in *next
 * the first byte after it that is not a space, tab or CR (the next number, or the LF ending the
 * line); NULL to leave anything else to bvh_number_padded. The whole token is classified at once
 * (16 bytes compared in SSE2), the '.' squeezed out of an 8-byte word, and all digits converted
 * by one bvh_swar8: about half the work of reading integer and fraction digits apart, and
 * finding the next number does not wait for the digits. */
BVH_INLINE const char *bvh_token_number(const char *s, double *out, const char **next)
{
    /* dividing by -10^k gives the sign for free, and exactly */
    static const double pow10[2][9] = {{1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8},
                                       {-1e0, -1e1, -1e2, -1e3, -1e4, -1e5, -1e6, -1e7, -1e8}};
    static const uint64_t bytes[9] = {0,
                                      0xFFull,
                                      0xFFFFull,
                                      0xFFFFFFull,
                                      0xFFFFFFFFull,
                                      0xFFFFFFFFFFull,
                                      0xFFFFFFFFFFFFull,
                                      0xFFFFFFFFFFFFFFull,
                                      0xFFFFFFFFFFFFFFFFull}; /* the low n bytes */
    __m128i b = _mm_loadu_si128((const __m128i *)(const void *)s);
    __m128i blank = _mm_or_si128(
        _mm_or_si128(_mm_cmpeq_epi8(b, _mm_set1_epi8(' ')), _mm_cmpeq_epi8(b, _mm_set1_epi8('\t'))),
        _mm_cmpeq_epi8(b, _mm_set1_epi8('\r')));
    unsigned blanks = (unsigned)_mm_movemask_epi8(blank);
    unsigned lf = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(b, _mm_set1_epi8('\n')));
    unsigned len = (unsigned)__builtin_ctz(blanks | lf | 0x10000u), neg = *s == '-';
    unsigned dots = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(b, _mm_set1_epi8('.')));
    dots &= (1u << len) - 1;
    unsigned n = len - neg - (dots != 0); /* digits, if the token is a number */
    if (n - 1 >= 8 || (dots & (dots - 1)))
        return 0;
    uint64_t w;
    memcpy(&w, s + neg, 8);
    unsigned dp = dots ? (unsigned)__builtin_ctz(dots) - neg : n; /* digits before the '.' */
    /* move the bytes after the '.' down one, and the 9th byte into the top (no-op without '.') */
    uint64_t high = (w >> 8) | ((uint64_t)(unsigned char)s[neg + 8] << 56);
    w = (w & bytes[dp]) | (high & ~bytes[dp]);
    uint64_t d = w - 0x3030303030303030ull;
    if ((d | (w + 0x4646464646464646ull)) & 0x8080808080808080ull & bytes[n])
        return 0; /* not all digits: an exponent, a '+', a stray character */
    /* m < 10^8: exact, and so is 10^(digits after the '.'): one correctly rounded division */
    *out = (double)bvh_swar8(d << (64 - 8 * n)) / pow10[neg][n - dp];
    unsigned after = ~blanks & (0xFFFFu << len) & 0xFFFFu;
    const char *q = s + (after ? (unsigned)__builtin_ctz(after) : 16u);
    while (*q == ' ' || *q == '\t' || *q == '\r') /* only after 16 bytes of token and blanks */
        q++;
    *next = q;
    return s + len;
}
#else
#define BVH_TOKEN 0
#endif

#if BVH_TOKEN && defined(__x86_64__) && defined(__GNUC__) && !defined(__clang_analyzer__)
#include <immintrin.h>
#define BVH_TOKEN_AVX2 1

/* Entries of bvh_short_avx2's shuffle table: one per leading '-' (0 or 1), digits before the '.'
 * (0..8) and digits in all (0..8). */
#define BVH_SHUFFLES (2 * 9 * 9)

/* Fills shuf[BVH_SHUFFLES]: entry (neg * 9 + i) * 9 + n moves the n digits of a token with neg
 * leading '-' and i digits before its '.' (n when it has none) to bytes 8 - n .. 7, the first
 * digit lowest, skipping the '.'; every other byte becomes 0 (an index with its high bit set). */
static inline void bvh_shuffles_init(uint8_t (*shuf)[16])
{
    for (int neg = 0; neg < 2; neg++)
        for (int i = 0; i <= 8; i++)
            for (int n = 0; n <= 8; n++) {
                uint8_t *e = shuf[(neg * 9 + i) * 9 + n];
                for (int k = 0; k < 16; k++) {
                    int j = k - (8 - n); /* the digit that lands in byte k */
                    e[k] = k < 8 && j >= 0 ? (uint8_t)(neg + j + (j >= i)) : 0x80;
                }
            }
}

/* bvh_short_avx2's byte constants, made once a line (bvh_avx2_k_init). */
typedef struct bvh_avx2_k {
    __m128i pt, zero, nine;
} bvh_avx2_k;

__attribute__((target("avx2"))) static inline void bvh_avx2_k_init(bvh_avx2_k *k)
{
    k->pt = _mm_set1_epi8('.'), k->zero = _mm_set1_epi8('0'), k->nine = _mm_set1_epi8(9);
    /* hidden from the optimiser, which would otherwise build each again from an immediate at
     * every number (a move, a vmovd and a broadcast each) instead of keeping it in a register */
    __asm__("" : "+x"(k->pt), "+x"(k->zero), "+x"(k->nine));
}

/* The token of len bytes at s (16 readable bytes) when it is a number of at most 8 digits with
 * an optional leading '-' and one '.': its value in *out, true; false to leave it to
 * bvh_number_padded. For processors with AVX2 (which have SSSE3's byte shuffles and SSE4.1's
 * packs): the digits are moved into place by one shuffle from the table above and converted by
 * two multiply-adds and a pack, 8 digits at once. The same tokens as bvh_token_number are taken
 * and the same value made (the digits' integer divided by a power of ten, exact). */
__attribute__((target("avx2"))) static inline bool bvh_short_avx2(const char *s, unsigned len,
                                                                  double *out,
                                                                  const uint8_t (*shuf)[16],
                                                                  const bvh_avx2_k *k)
{
    /* dividing by -10^k gives the sign for free, and exactly */
    static const double pow10[2][9] = {{1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8},
                                       {-1e0, -1e1, -1e2, -1e3, -1e4, -1e5, -1e6, -1e7, -1e8}};
    if (len > 10)
        return false; /* more than '-', 8 digits and '.' */
    __m128i b = _mm_loadu_si128((const __m128i *)(const void *)s);
    unsigned neg = *s == '-', token = (1u << len) - 1;
    unsigned dots = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(b, k->pt)) & token;
    unsigned dot = dots != 0, n = len - neg - dot; /* digits, if the token is a number */
    __m128i d = _mm_sub_epi8(b, k->zero);
    unsigned digit = (unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(d, k->nine), d));
    /* every byte of the token a digit but a leading '-' and the first '.' (a second is not) */
    if (n - 1 >= 8 || ((digit | neg | (dots & -dots)) & token) != token)
        return false;
    unsigned i = dot ? (unsigned)__builtin_ctz(dots) - neg : n; /* digits before the '.' */
    __m128i m = _mm_shuffle_epi8(
        d, _mm_loadu_si128((const __m128i *)(const void *)shuf[(neg * 9 + i) * 9 + n]));
    m = _mm_maddubs_epi16(m, _mm_set1_epi16(0x010A));  /* pairs: 10 a + b */
    m = _mm_madd_epi16(m, _mm_set1_epi32(0x00010064)); /* quads: 100 ab + cd */
    m = _mm_packus_epi32(m, m);                        /* each quad below 10^4 */
    m = _mm_madd_epi16(m, _mm_set1_epi32(0x00012710)); /* 10^4 abcd + efgh */
    /* m < 10^8: exact, and so is 10^(digits after the '.'): one correctly rounded division */
    *out = (double)_mm_cvtsi128_si32(m) / pow10[neg][n - i];
    return true;
}

/* Work space bvh_line_avx2 needs for a line of `count` numbers (uint32_t each). */
#define BVH_LINE_POS(count) (2 * ((count) + 1))

/* The numbers of one frame line [line, end) (end at its '\n' or NUL, BVH_PAD readable bytes after
 * it) into v[count], with pos[BVH_LINE_POS(count)] as work space. True only when the line holds
 * exactly `count` numbers separated by spaces, tabs or CRs, each of magnitude below 1e15; false
 * for anything else, which the caller then reads the careful way to say what is wrong.
 * Where each number starts and ends is found first, for the whole line, 32 bytes at a time from
 * bit masks; the numbers are then read independently of each other. Finding the next number
 * from the end of the one before made every number wait about 20 cycles on its predecessor;
 * this way the processor overlaps several. */
__attribute__((target("avx2"))) static inline bool
bvh_line_avx2(const char *line, const char *end, double *v, size_t count, uint32_t *pos,
              const uint8_t (*shuf)[16], const bvh_avx2_k *k)
{
    size_t len = (size_t)(end - line), n = 0, m = 0;
    if (len > UINT32_MAX - 64)
        return false;
    uint32_t *start = pos, *stop = pos + count + 1;
    __m256i sp = _mm256_set1_epi8(' '), tab = _mm256_set1_epi8('\t'), cr = _mm256_set1_epi8('\r');
    uint32_t carry = 1; /* the byte before the line counts as a blank */
    for (size_t at = 0; at <= len; at += 32) {
        __m256i b = _mm256_loadu_si256((const __m256i *)(const void *)(line + at));
        __m256i blank =
            _mm256_or_si256(_mm256_or_si256(_mm256_cmpeq_epi8(b, sp), _mm256_cmpeq_epi8(b, tab)),
                            _mm256_cmpeq_epi8(b, cr));
        uint32_t bits = (uint32_t)_mm256_movemask_epi8(blank);
        if (len - at < 32)
            bits |= ~UINT32_C(0) << (len - at); /* the end and after: blank */
        uint32_t before = (bits << 1) | carry;  /* bit i: byte i - 1 is a blank */
        uint32_t starts = ~bits & before, ends = bits & ~before;
        carry = bits >> 31;
        for (; starts; starts &= starts - 1, n++) {
            if (n == count)
                return false; /* more numbers than channels */
            start[n] = (uint32_t)(at + (unsigned)__builtin_ctz(starts));
        }
        for (; ends; ends &= ends - 1) /* as many as starts: the line ends in blanks */
            stop[m++] = (uint32_t)(at + (unsigned)__builtin_ctz(ends));
    }
    if (n != count)
        return false;
    for (size_t i = 0; i < count; i++) {
        const char *s = line + start[i];
        unsigned tl = stop[i] - start[i];
        if (!bvh_short_avx2(s, tl, v + i, shuf, k)) {
            const char *e = bvh_number_padded(s, v + i);
            if (e != s + tl || !(fabs(v[i]) < 1e15))
                return false;
        }
    }
    return true;
}
#else
#define BVH_TOKEN_AVX2 0
#endif

#endif
