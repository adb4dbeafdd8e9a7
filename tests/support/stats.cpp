#include "support/stats.hpp"
