/* rigflow SDK: text from files, made safe to print.
 *
 * Joint, clip and mesh names come from files anyone may have written. Printed raw, an ESC
 * sequence in a BVH joint name sets a terminal's title or colours, and a C1 control (U+0080 to
 * U+009F, or a stray 0x9b byte) does the same on terminals that honour them. Everything that
 * prints a name (the host's messages, `rigflow inspect`, `rigflow map --explain`, a plugin's own
 * report on a terminal or in a log) passes it through here first: printable UTF-8 is kept as it
 * is, and every control byte, C1 control and byte that is not valid UTF-8 becomes `\xNN`.
 */
#ifndef RIGFLOW_TEXT_H
#define RIGFLOW_TEXT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <rigflow/model.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Flags of rf_text_escape. */
enum rf_text_flags {
    RF_TEXT_KEEP_LINES = 1u << 0, /* keep '\n' and '\t' (multi-line messages) */
};

/* How many bytes at `s` (NUL-terminated) form one printable UTF-8 character, or 0 when the first
 * byte must be escaped: a control, DEL, a C1 control, or not the start of valid UTF-8 (overlong
 * forms, surrogates and code points beyond U+10FFFF are not). */
static inline size_t rf_text_printable_len(const unsigned char *s, uint32_t flags)
{
    unsigned char b = s[0];
    if (b < 0x20)
        return (flags & RF_TEXT_KEEP_LINES) && (b == '\n' || b == '\t') ? 1 : 0;
    if (b < 0x7f)
        return 1;
    if (b == 0x7f || b < 0xc2 || b > 0xf4)
        return 0;
    size_t n = b < 0xe0 ? 2 : b < 0xf0 ? 3 : 4;
    unsigned char lo = 0x80, hi = 0xbf; /* the second byte's range, narrower after some leads */
    if (b == 0xc2)
        lo = 0xa0; /* U+0080..U+009F are the C1 controls */
    else if (b == 0xe0)
        lo = 0xa0; /* overlong */
    else if (b == 0xed)
        hi = 0x9f; /* surrogates */
    else if (b == 0xf0)
        lo = 0x90; /* overlong */
    else if (b == 0xf4)
        hi = 0x8f; /* beyond U+10FFFF */
    if (s[1] < lo || s[1] > hi)
        return 0;
    for (size_t i = 2; i < n; i++)
        if (s[i] < 0x80 || s[i] > 0xbf)
            return 0;
    return n;
}

/* Length of the valid UTF-8 sequence at `s` (1 to 4 bytes; ASCII, controls included, is 1), or 0
 * at NUL or where no valid sequence starts (overlong forms, surrogates, beyond U+10FFFF); its code
 * point into *cp when cp is not NULL. */
static inline size_t rf_text_utf8_len(const unsigned char *s, uint32_t *cp)
{
    unsigned char b = s[0];
    size_t n = b == 0     ? 0
               : b < 0x80 ? 1
               : b < 0xc2 ? 0
               : b < 0xe0 ? 2
               : b < 0xf0 ? 3
               : b < 0xf5 ? 4
                          : 0;
    uint32_t c = n == 1 ? b : b & (0x7f >> n);
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;
        c = c << 6 | (s[i] & 0x3f);
    }
    static const uint32_t least[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (n == 0 || c < least[n] || c > 0x10ffff || (c >= 0xd800 && c <= 0xdfff))
        return 0;
    if (cp)
        *cp = c;
    return n;
}

/* `text` (NULL reads as "") with every byte that is not printable UTF-8 written as \xNN, into
 * `out` (`size` bytes, always NUL-terminated when size > 0, cut only between characters).
 * Returns the length the whole escaped text needs, as snprintf does. */
static inline size_t rf_text_escape(const char *text, char *out, size_t size, uint32_t flags)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *s = (const unsigned char *)(text ? text : "");
    size_t need = 0, kept = 0; /* bytes the whole needs; bytes written to out */
    bool room = size > 0;
    while (*s) {
        size_t n = rf_text_printable_len(s, flags);
        char esc[4] = {'\\', 'x', hex[*s >> 4], hex[*s & 15]};
        const char *piece = n ? (const char *)s : esc;
        size_t len = n ? n : 4;
        if (room && kept + len < size) {
            memcpy(out + kept, piece, len);
            kept += len;
        } else {
            room = false;
        }
        need += len;
        s += n ? n : 1;
    }
    if (size)
        out[kept] = '\0';
    return need;
}

/* Writes `text` (NULL reads as "") to `f`, escaped as rf_text_escape does. */
static inline void rf_text_fputs(const char *text, FILE *f, uint32_t flags)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *s = (const unsigned char *)(text ? text : "");
    while (*s) {
        size_t n = rf_text_printable_len(s, flags);
        if (n) {
            fwrite(s, 1, n, f);
            s += n;
        } else {
            char esc[4] = {'\\', 'x', hex[*s >> 4], hex[*s & 15]};
            fwrite(esc, 1, 4, f);
            s++;
        }
    }
}

/* v as it should be printed with `decimals` places ("%.2f", "%+.1f"): a value that shows as
 * zero at that precision comes back as +0.0, so a figure a hair under zero (a floor at
 * -2e-9 of the height) or a negative zero prints "0.00" or "+0.0", never "-0.00". The one home
 * for that rule: every printed signed figure that may sit at zero passes through here. */
static inline double rf_text_shown_zero(double v, int decimals)
{
    char b[512];
    int n = snprintf(b, sizeof b, "%.*f", decimals, v);
    if (n <= 1 || (size_t)n >= sizeof b || b[0] != '-')
        return v;
    return strspn(b + 1, "0.") == (size_t)(n - 1) ? 0.0 : v;
}

/* Joint `j` of `s` for a listing: its name escaped as above, or "#j" when it has none (or `s`
 * is NULL), in `buf` (`size` bytes). Returns buf. */
static inline const char *rf_joint_label(const rf_skeleton *s, uint32_t j, char *buf, size_t size)
{
    if (s && j < s->joint_count && s->joints[j].name)
        rf_text_escape(s->joints[j].name, buf, size, 0);
    else
        snprintf(buf, size, "#%u", j);
    return buf;
}

/* The refusal of a skeleton whose joint `j` (rf_skeleton_misordered) does not come after its
 * parent, both named by index and escaped name: "joint 3 'toe' has parent 7 '#7': expected
 * parents before children" ('#7': no such joint, or no name), into `buf`. Returns buf. */
static inline const char *rf_skeleton_order_error(const rf_skeleton *s, uint32_t j, char *buf,
                                                  size_t size)
{
    char joint[160], parent[160];
    uint32_t p = (uint32_t)s->joints[j].parent;
    snprintf(buf, size, "joint %u '%s' has parent %u '%s': expected parents before children", j,
             rf_joint_label(s, j, joint, sizeof joint), p,
             rf_joint_label(s, p, parent, sizeof parent));
    return buf;
}

#ifdef __cplusplus
}
#endif

#endif
