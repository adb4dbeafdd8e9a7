#pragma once
// Statistical test harness (chi-square goodness of fit of samplers against their pdf, furnace
// integrals). Filled in with the BSDF work.
namespace hydrolux::test {}
