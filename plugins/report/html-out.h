/* Writing data into an HTML page safely: JSON text that can sit inside
 * <script type="application/json"> (every '<', '>' and '&' escaped, so no byte of a file can close
 * the element or start markup), strings made valid UTF-8, numbers that are never NaN or infinity
 * (null instead), and float arrays as base64 so large clips stay compact. */
#ifndef RF_REPORT_HTML_OUT_H
#define RF_REPORT_HTML_OUT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* A JSON string of `s` (NULL writes null), quoted. Invalid UTF-8 becomes U+FFFD; control
 * characters, quotes, backslashes, '<', '>', '&', U+2028 and U+2029 are written as escapes. */
void rf_html_json_string(FILE *f, const char *s);

/* A JSON number with 7 significant digits, or null when not finite. */
void rf_html_json_number(FILE *f, double v);

/* `n` bytes as base64 (no quotes, no line breaks). */
void rf_html_base64(FILE *f, const unsigned char *data, size_t n);

/* `n` floats as a quoted base64 string of their little-endian IEEE bytes (Float32Array). */
void rf_html_json_floats(FILE *f, const float *v, size_t n);

/* Copies the file at `path` into f. Returns 0, or -1 when it cannot be read. */
int rf_html_copy_file(FILE *f, const char *path);

#endif
