#pragma once
// A fixture for tests/layers: a core header that includes the engine, against the direction.
#include "micromacro/engine/high.hpp"
