/* The slow path of the number parser: numbers with more than 19 significant digits, a mantissa
 * above 2^53 or a large exponent. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bvh-num.h"
#include "bvh.h"

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
