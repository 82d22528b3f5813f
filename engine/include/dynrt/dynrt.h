#pragma once
// The dynrt library API: include this one header. See api/engine.h for how to use it and
// docs/library-api.md "Library API" for a complete example.

#include "dynrt/api/distribute.h"
#include "dynrt/api/engine.h"
#include "dynrt/api/error.h"
#include "dynrt/api/types.h"
#include "dynrt/engine/frame_stats.h"
