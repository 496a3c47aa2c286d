// The former name of swarm.h, still included by particles_test.cpp and the leak harness (tests/leak/).
// New code includes swarm.h and names dng::testing::Swarm.
#pragma once

#include "swarm.h"
