#pragma once
// A fixture for tests/layers: an engine header, included from below.
#include "micromacro/core/low.hpp"
