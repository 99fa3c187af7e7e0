/* JSON and base64 for the HTML report: see html-out.h for the escaping rules. */
#include "config.h"

#include <math.h>
#include <string.h>

#include <rigflow/text.h>

#include "html-out.h"

void rf_html_json_string(FILE *f, const char *str)
{
    if (!str) {
        fputs("null", f);
        return;
    }
    const unsigned char *s = (const unsigned char *)str;
    fputc('"', f);
    while (*s) {
        unsigned char c = *s;
        if (c == '"' || c == '\\') {
            fputc('\\', f), fputc(c, f), s++;
        } else if (c < 0x20 || c == 0x7f || c == '<' || c == '>' || c == '&') {
            fprintf(f, "\\u%04x", c), s++;
        } else if (c < 0x80) {
            fputc(c, f), s++;
        } else {
            uint32_t cp = 0;
            size_t n = rf_text_utf8_len(s, &cp);
            if (!n)
                fputs("\\ufffd", f), s++;
            else if (cp == 0x2028 || cp == 0x2029 || (cp >= 0x80 && cp < 0xa0))
                fprintf(f, "\\u%04x", (unsigned)cp), s += n;
            else
                fwrite(s, 1, n, f), s += n;
        }
    }
    fputc('"', f);
}

void rf_html_json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.7g", v);
    else
        fputs("null", f);
}

void rf_html_base64(FILE *f, const unsigned char *d, size_t n)
{
    static const char abc[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char out[4];
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)d[i] << 16;
        if (i + 1 < n)
            v |= (uint32_t)d[i + 1] << 8;
        if (i + 2 < n)
            v |= d[i + 2];
        out[0] = abc[v >> 18 & 63], out[1] = abc[v >> 12 & 63];
        out[2] = i + 1 < n ? abc[v >> 6 & 63] : '=';
        out[3] = i + 2 < n ? abc[v & 63] : '=';
        fwrite(out, 1, 4, f);
    }
}

void rf_html_json_floats(FILE *f, const float *v, size_t n)
{
    unsigned char buf[3 * 256 * 4]; /* a multiple of 3 bytes: no padding inside the stream */
    size_t used = 0;
    fputc('"', f);
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &v[i], 4);
        for (int b = 0; b < 4; b++)
            buf[used++] = (unsigned char)(u >> (8 * b));
        if (used == sizeof buf)
            rf_html_base64(f, buf, used), used = 0;
    }
    rf_html_base64(f, buf, used);
    fputc('"', f);
}

int rf_html_copy_file(FILE *f, const char *path)
{
    FILE *in = fopen(path, "rb");
    if (!in)
        return -1;
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        fwrite(buf, 1, n, f);
    int bad = ferror(in);
    fclose(in);
    return bad ? -1 : 0;
}
