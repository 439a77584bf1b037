// The protocol cores of inmoov-dsl: pure C++, no Arduino dependency.
#ifndef INMOOV_DSL_H
#define INMOOV_DSL_H

#include "glove_core.h"
#include "inmoov_protocol.h"
#include "pose_store.h"
#include "servo_core.h"

#endif
