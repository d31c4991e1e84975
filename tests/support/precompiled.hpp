// The headers nearly every test includes, parsed once per test executable (CMake's precompiled header) instead of
// once per file: the engine's whole model and step (Eigen, oneTBB's flow graph, spdlog) is about half of a test
// file's compile time. Each test still includes what it uses, so it builds without this header too
// (-DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "tests/support/scene_builder.hpp"
#include "tests/support/test_support.hpp"
