// The carriers' eight direction policies as one set, and their recompute in
// a background thread (the duel's machinery: fray/igraph/background.h).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "fray/igraph/background.h"
#include "fray/igraph/carry.h"

namespace fray::igraph {

Result<CarryPolicySet> computeCarryPolicies(const CarryGraph& g, const CarryWeights& w, int depth, const ProgressFn& progress) {
    if (auto st = validate(w); !st) return st.error();
    if (depth < 1 || depth > 64) return makeError("carry policy: depth must be 1-64, got " + std::to_string(depth));
    const auto t0 = std::chrono::steady_clock::now();
    // The eight in parallel; progress (and cancel) through one lock: the
    // caller's callback need not be thread-safe.
    std::mutex lock;
    std::array<double, kCarryDirections> done{};
    std::vector<Result<CarryPolicy>> out(kCarryDirections, makeError("not computed"));
    tbb::parallel_for(0, kCarryDirections, [&](int k) {
        const ProgressFn each = [&, k](double f, std::string_view stage) {
            const std::lock_guard<std::mutex> guard(lock);
            done[static_cast<std::size_t>(k)] = f;
            double sum = 0;
            for (double d : done) sum += d;
            return reportProgress(progress, sum / kCarryDirections, stage);
        };
        out[static_cast<std::size_t>(k)] = computeCarryPolicy(g, w, k, depth, each);
    });
    CarryPolicySet set;
    set.weights = w;
    set.depth = depth;
    for (auto& p : out) {
        if (!p) return p.error();
        set.policies.push_back(std::move(*p));
    }
    set.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return set;
}

struct CarryPolicyService::Impl {
    std::shared_ptr<const CarryGraph> graph;
    BackgroundRecompute<CarryPolicySet> work;
    Impl(std::shared_ptr<const CarryGraph> g, std::shared_ptr<const CarryPolicySet> initial) : graph(std::move(g)), work(std::move(initial)) {}
};

CarryPolicyService::CarryPolicyService(std::shared_ptr<const CarryGraph> graph, std::shared_ptr<const CarryPolicySet> initial)
    : impl_(std::make_unique<Impl>(std::move(graph), std::move(initial))) {}

CarryPolicyService::~CarryPolicyService() { impl_->work.stop(); }

std::shared_ptr<const CarryPolicySet> CarryPolicyService::current() const { return impl_->work.current(); }

Status CarryPolicyService::request(const CarryWeights& w, int depth) {
    if (auto st = validate(w); !st) return st;
    if (depth < 1 || depth > 64) return makeError("carry policy depth must be between 1 and 64, got " + std::to_string(depth));
    impl_->work.start([graph = impl_->graph, w, depth](const ProgressFn& progress) { return computeCarryPolicies(*graph, w, depth, progress); });
    return {};
}

bool CarryPolicyService::busy() const { return impl_->work.busy(); }

Status CarryPolicyService::wait() { return impl_->work.wait(); }

}  // namespace fray::igraph
