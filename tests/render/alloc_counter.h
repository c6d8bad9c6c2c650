#pragma once
// Number of global operator new calls so far in this process (the test binary
// replaces operator new; see alloc_counter.cpp).
namespace fray::render::test {
long allocationCount();
}
