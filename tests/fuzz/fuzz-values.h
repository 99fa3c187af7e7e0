/* Values the fuzz harnesses build their inputs from (header only: each harness is one program).
 */
#ifndef RIGFLOW_FUZZ_VALUES_H
#define RIGFLOW_FUZZ_VALUES_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include <rigflow/rfmath.h>

/* Identity, quarter turns, a non-unit and a zero quaternion, and for b & 7 == 6 a NaN one when
 * `nan` (else another non-unit one): a harness whose inputs are refused on any NaN asks for it
 * rarely, so that most inputs get past the checks. */
static inline rf_quat rf_fz_quat_of(uint8_t b, bool nan)
{
    const double h = sqrt(0.5);
    switch (b & 7) {
    case 1:
        return rf_quat_make(h, 0, 0, h);
    case 2:
        return rf_quat_make(0, h, 0, h);
    case 3:
        return rf_quat_make(0, 0, h, h);
    case 4:
        return rf_quat_make(0.3, 0.1 * (b >> 3), 0.2, 0.9);
    case 5:
        return rf_quat_make(0, 0, 0, 0);
    case 6:
        return nan ? rf_quat_make(NAN, 0, 0, 1) : rf_quat_make(0.1 * (b >> 3), -1, 0.5, 0);
    case 7:
        return rf_quat_make(1, 0, 0, 0);
    default:
        return rf_quat_make(0, 0, 0, 1);
    }
}

#endif
