/* The slow path of the number parser: numbers with more than 19 significant digits, a mantissa
 * above 2^53 or a large exponent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bvh-num.h"
#include "rigflow/bvh.h"

const char *rf_bvh_parse_double(const char *s, double *out)
{
    return bvh_number(s, out);
}

/* Appends the exponent `e` in decimal to buf at n; returns the new length. */
static size_t put_exponent(char *buf, size_t n, long long e)
{
    char tmp[32];
    int len = snprintf(tmp, sizeof tmp, "e%lld", e);
    memcpy(buf + n, tmp, (size_t)len);
    return n + (size_t)len;
}

const char *rf_bvh_parse_slow(const char *s, const char *end, double *out)
{
    /* strtod's only locale-dependent part for such a token is the decimal point, so rewrite
     * "123.456e7" as "123456e4": digits and an exponent mean the same in every locale. */
    size_t len = (size_t)(end - s);
    char local[256];
    char *buf = len + 40 <= sizeof local ? local : malloc(len + 40);
    if (!buf)
        return 0;
    size_t n = 0;
    long long frac_digits = 0, e = 0;
    const char *p = s;
    if (*p == '-' || *p == '+')
        buf[n++] = *p++;
    for (; p < end && bvh_is_digit(*p); p++)
        buf[n++] = *p;
    if (p < end && *p == '.')
        for (p++; p < end && bvh_is_digit(*p); p++, frac_digits++)
            buf[n++] = *p;
    if (p < end && (*p == 'e' || *p == 'E')) {
        bool eneg = *++p == '-';
        if (*p == '-' || *p == '+')
            p++;
        for (; p < end && bvh_is_digit(*p); p++)
            if (e < 1000000000000LL)
                e = e * 10 + (*p - '0');
        if (eneg)
            e = -e;
    }
    n = put_exponent(buf, n, e - frac_digits);
    buf[n] = '\0';
    char *stop;
    *out = strtod(buf, &stop);
    bool ok = stop == buf + n;
    if (buf != local)
        free(buf);
    return ok ? end : 0;
}

/* Writes the P significant digits of m (10^(P-1) <= m < 10^P) as %g's fixed notation for the
 * decimal exponent e10 (-4 <= e10 < P): point placed, trailing fraction zeros dropped. */
static int fixed_digits(char *out, uint64_t m, int precision, int e10)
{
    char d[20];
    for (int i = precision - 1; i >= 0; i--, m /= 10)
        d[i] = (char)('0' + m % 10);
    int last = precision - 1, n = 0;
    int int_digits = e10 >= 0 ? e10 + 1 : 0;
    while (last >= int_digits && d[last] == '0')
        last--;
    if (e10 < 0) {
        out[n++] = '0';
        out[n++] = '.';
        for (int z = 0; z < -e10 - 1; z++)
            out[n++] = '0';
    }
    for (int i = 0; i <= last; i++) {
        if (i == int_digits && e10 >= 0)
            out[n++] = '.';
        out[n++] = d[i];
    }
    return n;
}

int rf_bvh_format_number(char *buf, size_t size, int precision, double v)
{
    static const double pow10[19] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8, 1e9,
                                     1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18};
    if (v == 0)
        v = 0; /* -0 prints as 0 */
    double a = fabs(v);
    /* The fast way: %g's fixed notation (decimal exponent -4 .. P-1) with P <= 15 digits, so the
     * rounded digits fit a double exactly. a * 10^k is one rounding away from the exact product;
     * unless that leaves the digit rounding in doubt (within 2 ulps of a half), the digits are
     * the ones printf would give. Anything else goes to snprintf. */
    if (BVH_FAST_PATH && precision >= 1 && precision <= 15 && size >= 32 && a >= 1e-4 &&
        a < pow10[precision]) {
        int e10 = 0; /* a first guess of the decimal exponent; the loop below corrects it */
        if (a >= 1)
            while (e10 < precision && a >= pow10[e10 + 1])
                e10++;
        else
            for (double t = a * 10; t < 1 && e10 > -5; t *= 10)
                e10--;
        if (a < 1)
            e10--;
        for (int tries = 0; tries < 3; tries++) {
            int k = precision - 1 - e10;
            if (e10 < -4 || e10 >= precision || k < 0 || k > 18)
                break;
            double scaled = a * pow10[k], fl = floor(scaled), frac = scaled - fl;
            if (fabs(frac - 0.5) <= 4.5e-16 * scaled)
                break;
            uint64_t m = (uint64_t)fl + (frac > 0.5);
            if (m < (uint64_t)pow10[precision - 1]) {
                e10--;
                continue;
            }
            if (m > (uint64_t)pow10[precision]) {
                e10++;
                continue;
            }
            if (m == (uint64_t)pow10[precision]) { /* 9.99.. rounded up to 10.0.. */
                m /= 10;
                if (++e10 >= precision)
                    break;
            }
            int n = 0;
            if (v < 0)
                buf[n++] = '-';
            n += fixed_digits(buf + n, m, precision, e10);
            buf[n] = '\0';
            return n;
        }
    }
    return snprintf(buf, size, "%.*g", precision, v);
}
