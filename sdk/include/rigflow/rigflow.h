/* rigflow SDK: everything a plugin needs, in one include. */
#ifndef RIGFLOW_RIGFLOW_H
#define RIGFLOW_RIGFLOW_H

#include "version.h"
#include "rfmath.h"
#include "model.h"
#include "plugin.h"
#include "model-copy.h"

#endif
