// keel::lie — umbrella header for the Lie-group uncertainty engine.
#pragma once

#include "concepts.hpp"
#include "euler.hpp"
#include "gaussian.hpp"
#include "metrics.hpp"
#include "se2.hpp"
#include "se3.hpp"
#include "so2.hpp"
#include "so3.hpp"
#include "ssc.hpp"
#include "types.hpp"
#include "uncertain.hpp"
#include "unscented.hpp"
