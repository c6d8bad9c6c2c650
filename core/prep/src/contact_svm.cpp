// Supporting-foot SVM (SPEC 1.3): libsvm C-SVC with an RBF kernel, (C, gamma)
// chosen by a grid search scored with exact leave-one-out cross-validation.
#include <svm.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "fray/prep/contacts.h"

namespace fray::prep {
namespace {

// ---- libsvm plumbing ----------------------------------------------------

void quietPrint(const char* /*unused*/) {}

// libsvm prints training progress to stdout through one global hook; set it
// once, before any training, from whichever thread gets here first.
void silenceLibsvm() {
    static std::once_flag once;
    std::call_once(once, [] { svm_set_print_string_function(&quietPrint); });
}

struct ModelDeleter {
    void operator()(svm_model* m) const { svm_free_and_destroy_model(&m); }
};
using ModelPtr = std::unique_ptr<svm_model, ModelDeleter>;

// ---- features -----------------------------------------------------------

// Scaled features are rounded to a 1/4096 grid, in training and prediction
// alike: far below any meaningful difference (a speed ratio of 0.2 %), and
// it turns the many near-identical planted frames into exact duplicates,
// which training then holds once (see TrainingSet).
constexpr double kQuantSteps = 4096.0;

using Feature = std::array<double, 2>;
using Key = std::array<int, 2>;

double compress(double v, double ref) { return std::log2(1.0 + std::max(0.0, v) / ref); }

// Key of one feature value: an integer in [0, kQuantSteps]. A NaN reads as
// the far end of the range (fast, high: not supporting).
int quantise(double v, double ref, double lo, double hi) {
    if (std::isnan(v)) return static_cast<int>(kQuantSteps);
    const double t = std::clamp((compress(v, ref) - lo) / (hi - lo), 0.0, 1.0);
    return static_cast<int>(std::lround(t * kQuantSteps));
}

Key featureKey(const ContactSvm::Scaling& s, float speed, float height) {
    return {quantise(double(speed), s.speedRef, s.lo[0], s.hi[0]), quantise(double(height), s.heightRef, s.lo[1], s.hi[1])};
}

Feature keyToFeature(const Key& k) { return {k[0] / kQuantSteps, k[1] / kQuantSteps}; }

// ---- a plain copy of a two-class model ------------------------------------

// Decision value = sum_i coef_i * exp(-gamma |x - sv_i|^2) - rho; > 0 means
// supporting. Contact-class support vectors come first.
struct SvmData {
    double C = 0;
    double gamma = 0;
    double rho = 0;
    int nContact = 0;
    std::vector<Feature> sv;
    std::vector<double> coef;
};

double nodeValue(const svm_node* node, int index) {
    for (; node->index != -1; ++node)
        if (node->index == index) return node->value;
    return 0.0;  // libsvm's sparse convention
}

// Copies a trained model, reordered so the contact class (+1) is first and a
// positive decision means contact whatever libsvm's internal label order.
SvmData extract(const svm_model* m) {
    SvmData d;
    d.C = m->param.C;
    d.gamma = m->param.gamma;
    const double sign = m->label[0] == 1 ? 1.0 : -1.0;
    d.rho = sign * m->rho[0];
    const int n0 = m->nSV[0];
    for (int pass = 0; pass < 2; ++pass) {  // pass 0: contact SVs, pass 1: the others
        for (int i = 0; i < m->l; ++i) {
            const int label = i < n0 ? m->label[0] : m->label[1];
            if ((label == 1) != (pass == 0)) continue;
            d.sv.push_back({nodeValue(m->SV[i], 1), nodeValue(m->SV[i], 2)});
            d.coef.push_back(sign * m->sv_coef[0][i]);
            if (pass == 0) ++d.nContact;
        }
    }
    return d;
}

// Builds a self-contained libsvm model (the layout svm_load_model makes, so
// svm_free_and_destroy_model frees it). Null when out of memory.
ModelPtr buildModel(const SvmData& d) {
    const int l = static_cast<int>(d.sv.size());
    ModelPtr m(static_cast<svm_model*>(std::calloc(1, sizeof(svm_model))));
    if (!m || l <= 0) return nullptr;
    m->param.svm_type = C_SVC;
    m->param.kernel_type = RBF;
    m->param.gamma = d.gamma;
    m->param.C = d.C;
    m->nr_class = 2;
    m->l = l;
    m->free_sv = 1;
    m->SV = static_cast<svm_node**>(std::calloc(static_cast<std::size_t>(l), sizeof(svm_node*)));
    m->sv_coef = static_cast<double**>(std::calloc(1, sizeof(double*)));
    m->rho = static_cast<double*>(std::malloc(sizeof(double)));
    m->label = static_cast<int*>(std::malloc(2 * sizeof(int)));
    m->nSV = static_cast<int*>(std::malloc(2 * sizeof(int)));
    if (!m->SV || !m->sv_coef || !m->rho || !m->label || !m->nSV) return nullptr;
    auto* nodes = static_cast<svm_node*>(std::malloc(3 * static_cast<std::size_t>(l) * sizeof(svm_node)));
    m->sv_coef[0] = static_cast<double*>(std::malloc(static_cast<std::size_t>(l) * sizeof(double)));
    if (!nodes || !m->sv_coef[0]) {
        std::free(nodes);
        return nullptr;
    }
    for (int i = 0; i < l; ++i) {
        const auto u = static_cast<std::size_t>(i);
        svm_node* x = nodes + 3 * u;
        x[0] = {1, d.sv[u][0]};
        x[1] = {2, d.sv[u][1]};
        x[2] = {-1, 0.0};
        m->SV[i] = x;
        m->sv_coef[0][i] = d.coef[u];
    }
    m->rho[0] = d.rho;
    m->label[0] = 1;
    m->label[1] = -1;
    m->nSV[0] = d.nContact;
    m->nSV[1] = l - d.nContact;
    return m;
}

double decisionValue(const svm_model* m, const Feature& f) {
    const svm_node x[3] = {{1, f[0]}, {2, f[1]}, {-1, 0.0}};
    double dec = 0.0;
    svm_predict_values(m, x, &dec);
    // A model from svm_train may hold the classes in either order.
    return m->label[0] == 1 ? dec : -dec;
}

// ---- training set -------------------------------------------------------

// The training rows after validation, subsampling, scaling, quantisation and
// de-duplication. Samples with the same quantised feature and label are one
// row with a weight: planted feet give hundreds of near-identical frames,
// which would only repeat one point of the problem (and slow libsvm down)
// while adding nothing to where the boundary lies. Every accuracy counts a
// row as many times as it has samples.
struct TrainingSet {
    ContactSvm::Scaling scaling;
    int samples = 0;
    std::vector<Feature> feature;
    std::vector<double> y;  // +1 contact, -1 free
    std::vector<long long> weight;
    std::vector<svm_node> nodes;  // 3 per row: speed, height, terminator
    std::vector<svm_node*> x;
    std::size_t size() const { return y.size(); }
};

Result<TrainingSet> prepare(const std::vector<TrainingSample>& samples, const SvmTrainOptions& options) {
    if (samples.empty()) {
        return makeError("no labelled frames to train the contact SVM: label some frames where a foot supports the "
                         "body and some where it is in the air");
    }
    std::size_t contacts = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (!std::isfinite(samples[i].speed) || !std::isfinite(samples[i].height))
            return makeError("training sample " + std::to_string(i) + " has a non-finite speed or height");
        contacts += samples[i].contact ? 1 : 0;
    }
    if (contacts == samples.size())
        return makeError("labels mark only supporting frames; label some frames where the foot is in the air too");
    if (contacts == 0)
        return makeError("labels mark only frames where the foot is in the air; label some supporting frames too");
    if (options.maxSamples < 2) return makeError("maxSamples must be at least 2");
    if (!(options.eps > 0.0) || !std::isfinite(options.eps)) return makeError("SVM tolerance eps must be positive");

    // An even stride: samples are in temporal order per foot.
    std::vector<TrainingSample> used;
    const auto maxSamples = static_cast<std::size_t>(options.maxSamples);
    if (samples.size() > maxSamples) {
        used.reserve(maxSamples);
        for (std::size_t i = 0; i < maxSamples; ++i) used.push_back(samples[i * samples.size() / maxSamples]);
        const auto c = std::count_if(used.begin(), used.end(), [](const TrainingSample& s) { return s.contact; });
        if (c == 0 || c == static_cast<std::ptrdiff_t>(used.size())) {
            return makeError("after subsampling to " + std::to_string(maxSamples) +
                             " samples only one class is left; raise maxSamples or label more of the rarer class");
        }
    } else {
        used = samples;
    }

    TrainingSet set;
    set.samples = static_cast<int>(used.size());
    for (int k = 0; k < 2; ++k) {
        const double ref = k == 0 ? set.scaling.speedRef : set.scaling.heightRef;
        double lo = HUGE_VAL;
        double hi = -HUGE_VAL;
        for (const auto& s : used) {
            const double v = compress(double(k == 0 ? s.speed : s.height), ref);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        if (!(hi - lo > 1e-9)) hi = lo + 1.0;  // a constant feature: any non-empty range
        set.scaling.lo[k] = lo;
        set.scaling.hi[k] = hi;
    }

    // Sorting by (key, label) makes the row order independent of the sample order.
    std::vector<std::array<int, 3>> keys(used.size());
    for (std::size_t i = 0; i < used.size(); ++i) {
        const Key k = featureKey(set.scaling, used[i].speed, used[i].height);
        keys[i] = {k[0], k[1], used[i].contact ? 1 : 0};
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size(); ++i) {
        if (i > 0 && keys[i] == keys[i - 1]) {
            ++set.weight.back();
            continue;
        }
        set.feature.push_back(keyToFeature({keys[i][0], keys[i][1]}));
        set.y.push_back(keys[i][2] ? 1.0 : -1.0);
        set.weight.push_back(1);
    }
    set.nodes.resize(3 * set.size());
    set.x.resize(set.size());
    for (std::size_t r = 0; r < set.size(); ++r) {
        svm_node* x = &set.nodes[3 * r];
        x[0] = {1, set.feature[r][0]};
        x[1] = {2, set.feature[r][1]};
        x[2] = {-1, 0.0};
        set.x[r] = x;
    }
    return set;
}

Status checkGrid(const SvmTrainOptions& options) {
    if (options.log2C.empty() || options.log2Gamma.empty()) return makeError("the SVM grid (C, gamma) is empty");
    for (const auto* axis : {&options.log2C, &options.log2Gamma}) {
        for (const double v : *axis)
            if (!std::isfinite(v) || std::abs(v) > 30.0)
                return makeError("SVM grid value 2^" + std::to_string(v) + " is outside 2^-30..2^30");
    }
    return {};
}

svm_parameter makeParam(double C, double gamma, double eps, std::size_t rows) {
    svm_parameter p{};
    p.svm_type = C_SVC;
    p.kernel_type = RBF;
    p.gamma = gamma;
    p.C = C;
    p.eps = eps;
    // Room for the whole kernel matrix (floats) when it is small; libsvm
    // allocates the cache lazily, column by column.
    const double matrixMb = 4.0 * static_cast<double>(rows) * static_cast<double>(rows) / (1024.0 * 1024.0);
    p.cache_size = std::clamp(matrixMb + 1.0, 4.0, 64.0);
    p.shrinking = 1;
    p.probability = 0;
    return p;
}

// Trains on the rows where use[r] != 0; rows gets the row of each problem index.
ModelPtr trainRows(const TrainingSet& set, const std::vector<std::uint8_t>& use, const svm_parameter& param,
                   std::vector<std::size_t>* rows = nullptr) {
    std::vector<double> y;
    std::vector<svm_node*> x;
    if (rows) rows->clear();
    for (std::size_t r = 0; r < use.size(); ++r) {
        if (!use[r]) continue;
        y.push_back(set.y[r]);
        x.push_back(set.x[r]);
        if (rows) rows->push_back(r);
    }
    const svm_problem problem{static_cast<int>(y.size()), y.data(), x.data()};
    return ModelPtr(svm_train(&problem, &param));
}

// Decision value of an extracted model (the function libsvm evaluates).
double evalDecision(const SvmData& d, const Feature& x) {
    double sum = -d.rho;
    for (std::size_t i = 0; i < d.sv.size(); ++i) {
        const double a = x[0] - d.sv[i][0];
        const double b = x[1] - d.sv[i][1];
        sum += d.coef[i] * std::exp(-d.gamma * (a * a + b * b));
    }
    return sum;
}

double rbfKernel(const TrainingSet& set, double gamma, std::size_t a, std::size_t b) {
    const double dx = set.feature[a][0] - set.feature[b][0];
    const double dy = set.feature[a][1] - set.feature[b][1];
    return std::exp(-gamma * (dx * dx + dy * dy));
}

// Kernel values between every row and the rows of one cell's working set
// (the columns), computed once per cell: the leave-one-out models' support
// vectors are almost all among those rows, so checking a model against every
// row is a dot product per row, without exp().
class KernelColumns {
public:
    KernelColumns(const TrainingSet& set, double gamma, const std::vector<std::uint8_t>& columns)
        : set_(set), gamma_(gamma), slot_(set.size(), -1) {
        std::vector<std::size_t> rows;
        for (std::size_t c = 0; c < set.size(); ++c) {
            if (!columns[c]) continue;
            slot_[c] = static_cast<int>(rows.size());
            rows.push_back(c);
        }
        columnCount_ = rows.size();
        values_.resize(set.size() * columnCount_);
        for (std::size_t r = 0; r < set.size(); ++r) {
            double* out = values_.data() + r * columnCount_;
            for (std::size_t k = 0; k < columnCount_; ++k) out[k] = rbfKernel(set, gamma, r, rows[k]);
        }
    }
    std::size_t columnCount() const { return columnCount_; }
    int slot(std::size_t row) const { return slot_[row]; }
    const double* row(std::size_t r) const { return values_.data() + r * columnCount_; }
    double rbf(std::size_t a, std::size_t b) const { return rbfKernel(set_, gamma_, a, b); }
    double operator()(std::size_t a, std::size_t b) const {
        if (slot_[b] >= 0) return row(a)[slot_[b]];
        if (slot_[a] >= 0) return row(b)[slot_[a]];
        return rbf(a, b);
    }

private:
    const TrainingSet& set_;
    double gamma_;
    std::vector<int> slot_;
    std::size_t columnCount_ = 0;
    std::vector<double> values_;  // row-major: values_[r * columnCount_ + slot]
};

// A trained model in terms of training rows, f(x_r) = sum coef_k K(r, row_k)
// - rho, split into the support vectors that are kernel columns (a dense
// coefficient per column) and the few that are not.
struct RowModel {
    std::vector<double> columnCoef;
    std::vector<std::size_t> otherRows;
    std::vector<double> otherCoef;
    double rho = 0;
    double operator()(const KernelColumns& k, std::size_t r) const {
        // Four partial sums (a fixed order, so still deterministic) let the
        // compiler vectorise the dot product, the hot loop of the checks.
        const double* values = k.row(r);
        const std::size_t n = columnCoef.size();
        double part[4] = {0, 0, 0, 0};
        std::size_t c = 0;
        for (; c + 4 <= n; c += 4)
            for (std::size_t j = 0; j < 4; ++j) part[j] += columnCoef[c + j] * values[c + j];
        double sum = (part[0] + part[1]) + (part[2] + part[3]) - rho;
        for (; c < n; ++c) sum += columnCoef[c] * values[c];
        for (std::size_t i = 0; i < otherRows.size(); ++i) sum += otherCoef[i] * k.rbf(r, otherRows[i]);
        return sum;
    }
};

RowModel rowModel(const svm_model* m, const std::vector<std::size_t>& problemRows, const KernelColumns& k) {
    RowModel out;
    out.columnCoef.assign(k.columnCount(), 0.0);
    std::vector<int> index(static_cast<std::size_t>(m->l));
    svm_get_sv_indices(m, index.data());
    const double sign = m->label[0] == 1 ? 1.0 : -1.0;
    for (int i = 0; i < m->l; ++i) {
        const std::size_t row = problemRows[static_cast<std::size_t>(index[static_cast<std::size_t>(i)] - 1)];
        const double coef = sign * m->sv_coef[0][i];
        if (k.slot(row) >= 0) {
            out.columnCoef[static_cast<std::size_t>(k.slot(row))] = coef;
        } else {
            out.otherRows.push_back(row);
            out.otherCoef.push_back(coef);
        }
    }
    out.rho = sign * m->rho[0];
    return out;
}

struct CellResult {
    long long correct = 0;  // leave-one-out, in samples (row weights)
    long long retrains = 0;
    SvmData model;
};

// Trains on the rows in `use` with libsvm's PRECOMPUTED kernel, the values
// taken from the cell's kernel columns: the same problem as with the RBF
// kernel, without an exp() per kernel value in every retraining. Each row's
// nodes are [serial, K(row, 1..m), end]; `nodes` keeps them alive (and is
// reused between calls).
ModelPtr trainPrecomputed(const TrainingSet& set, const std::vector<std::uint8_t>& use, const svm_parameter& rbfParam,
                          const KernelColumns& kernel, std::vector<std::size_t>& rows, std::vector<svm_node>& nodes) {
    rows.clear();
    for (std::size_t r = 0; r < use.size(); ++r)
        if (use[r]) rows.push_back(r);
    const std::size_t m = rows.size();
    nodes.resize(m * (m + 2));
    std::vector<svm_node*> x(m);
    std::vector<double> y(m);
    for (std::size_t i = 0; i < m; ++i) {
        svm_node* xi = &nodes[i * (m + 2)];
        xi[0] = {0, static_cast<double>(i + 1)};
        for (std::size_t j = 0; j < m; ++j) xi[j + 1] = {static_cast<int>(j + 1), kernel(rows[i], rows[j])};
        xi[m + 1] = {-1, 0.0};
        x[i] = xi;
        y[i] = set.y[rows[i]];
    }
    svm_parameter param = rbfParam;
    param.kernel_type = PRECOMPUTED;
    const svm_problem problem{static_cast<int>(m), y.data(), x.data()};
    return ModelPtr(svm_train(&problem, &param));
}

// True when `left` is the only row of its class: without it the problem has
// one class, and the leave-one-out model predicts the other one.
bool onlyRowOfItsClass(const TrainingSet& set, std::size_t left) {
    for (std::size_t r = 0; r < set.size(); ++r)
        if (r != left && set.y[r] == set.y[left]) return false;
    return true;
}

// Leave-one-out prediction of row `left` by libsvm on all other rows.
bool looBruteForce(const TrainingSet& set, std::size_t left, const svm_parameter& param) {
    if (onlyRowOfItsClass(set, left)) return false;
    std::vector<std::uint8_t> use(set.size(), 1);
    use[left] = 0;
    const ModelPtr m = trainRows(set, use, param);
    return m && set.y[left] * decisionValue(m.get(), set.feature[left]) > 0;
}

// The same prediction from a working set. libsvm solves the problem on the
// rows in `use` (the full model's support vectors and the rows inside its
// margin, minus `left`); a row outside the set keeps alpha = 0, which is
// optimal iff y g(x) >= 1 under the new model g. Every row is checked;
// violators join the set and libsvm runs again. When none is left, the
// working-set solution satisfies the KKT conditions of the whole
// leave-one-out problem, so (the problem being convex) it is its solution,
// within libsvm's tolerance eps.
bool looWorkingSet(const TrainingSet& set, std::size_t left, std::vector<std::uint8_t> use,
                   const std::vector<double>& margin, const svm_parameter& param, const KernelColumns& kernel) {
    if (onlyRowOfItsClass(set, left)) return false;
    use[left] = 0;
    // libsvm needs both classes: seed a missing one with its row nearest the boundary.
    for (const double y : {1.0, -1.0}) {
        std::size_t nearest = set.size();
        for (std::size_t r = 0; r < set.size(); ++r) {
            if (set.y[r] != y || r == left) continue;
            if (use[r]) {
                nearest = set.size();
                break;
            }
            if (nearest == set.size() || margin[r] < margin[nearest]) nearest = r;
        }
        if (nearest < set.size()) use[nearest] = 1;
    }
    std::vector<std::size_t> rows;
    std::vector<svm_node> nodes;
    for (;;) {
        const ModelPtr m = trainPrecomputed(set, use, param, kernel, rows, nodes);
        if (!m) return false;
        const RowModel g = rowModel(m.get(), rows, kernel);
        bool violated = false;
        for (std::size_t r = 0; r < set.size(); ++r) {
            if (use[r] || r == left) continue;
            if (set.y[r] * g(kernel, r) < 1.0 - param.eps) {
                use[r] = 1;
                violated = true;
            }
        }
        if (!violated) return set.y[left] * g(kernel, left) > 0;
    }
}

// Leave-one-out accuracy of one (C, gamma) from one full training plus a
// few small retrainings. Which rows need a retraining:
//  * A row that is not a support vector (alpha = 0) can be left out without
//    changing the optimum: the remaining alphas still satisfy every KKT
//    condition of the smaller problem. Its LOO prediction is the full
//    model's (correct, as y f >= 1 for such a row).
//  * A row the full model misclassifies stays misclassified without it: with
//    J = J_-i + C xi_i, the optimality of both models gives
//    xi_i(loo) >= xi_i(full) > 1, so y f_loo(x_i) < 0. (A margin of 10 eps
//    keeps the solver's tolerance from deciding.)
//  * The other support vectors are retrained without themselves
//    (looWorkingSet); brute force would retrain every row.
CellResult evaluateCell(const TrainingSet& set, double C, double gamma, double eps, LooMethod method,
                        const std::atomic<bool>& cancelled) {
    CellResult out;
    const svm_parameter param = makeParam(C, gamma, eps, set.size());
    const std::vector<std::uint8_t> all(set.size(), 1);
    const ModelPtr model = trainRows(set, all, param);
    if (!model) return out;
    out.model = extract(model.get());

    std::vector<int> svIndex(static_cast<std::size_t>(svm_get_nr_sv(model.get())));
    svm_get_sv_indices(model.get(), svIndex.data());
    std::vector<std::uint8_t> isSv(set.size(), 0);
    for (const int i : svIndex) isSv[static_cast<std::size_t>(i - 1)] = 1;  // 1-based

    const double marginTol = std::max(0.01, 10.0 * eps);
    std::vector<std::uint8_t> workingSet(set.size(), 0);
    std::vector<double> margin(set.size());
    std::vector<std::size_t> retrain;
    for (std::size_t r = 0; r < set.size(); ++r) {
        margin[r] = set.y[r] * evalDecision(out.model, set.feature[r]);
        workingSet[r] = isSv[r] || margin[r] < 1.0;
        if (method == LooMethod::BruteForce || (isSv[r] && margin[r] >= -marginTol)) {
            retrain.push_back(r);
        } else if (!isSv[r] && margin[r] > 0) {
            out.correct += set.weight[r];
        }
    }

    const bool shortcut = method == LooMethod::Shortcut;
    const KernelColumns kernel(set, gamma, shortcut ? workingSet : std::vector<std::uint8_t>(set.size()));
    std::vector<std::uint8_t> looCorrect(retrain.size(), 0);
    tbb::parallel_for(std::size_t{0}, retrain.size(), [&](std::size_t k) {
        if (cancelled.load(std::memory_order_relaxed)) return;
        looCorrect[k] = shortcut ? looWorkingSet(set, retrain[k], workingSet, margin, param, kernel)
                                 : looBruteForce(set, retrain[k], param);
    });
    for (std::size_t k = 0; k < retrain.size(); ++k)
        if (looCorrect[k]) out.correct += set.weight[retrain[k]];
    out.retrains = static_cast<long long>(retrain.size());
    return out;
}

// ---- binary format ------------------------------------------------------

constexpr std::uint8_t kMagic[4] = {'F', 'R', 'S', 'V'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 4 + 4 + 10 * 8 + 3 * 4;
constexpr std::size_t kSvBytes = 3 * 8;
constexpr std::uint32_t kMaxSvPerClass = 1u << 24;

void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void putF64(std::vector<std::uint8_t>& out, double d) {
    const auto v = std::bit_cast<std::uint64_t>(d);
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

struct Reader {
    std::span<const std::uint8_t> bytes;
    std::size_t pos = 0;
    bool u32(std::uint32_t& v) {
        if (bytes.size() - pos < 4) return false;
        v = 0;
        for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(bytes[pos++]) << (8 * i);
        return true;
    }
    bool f64(double& d) {
        if (bytes.size() - pos < 8) return false;
        std::uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(bytes[pos++]) << (8 * i);
        d = std::bit_cast<double>(v);
        return true;
    }
};

}  // namespace

// Builds ContactSvm objects (the constructor is private).
struct ContactSvmAccess {
    static Result<ContactSvm> make(const SvmData& data, const ContactSvm::Scaling& scaling, SvmReport report) {
        ModelPtr model = buildModel(data);
        if (!model) return makeError("out of memory building the contact SVM");
        ContactSvm svm;
        svm.model_ = model.release();
        svm.scaling_ = scaling;
        svm.report_ = std::move(report);
        svm.report_.supportVectors = static_cast<int>(data.sv.size());
        return svm;
    }
    static SvmData data(const ContactSvm& svm) { return extract(svm.model_); }
};

ContactSvm::ContactSvm(ContactSvm&& other) noexcept
    : model_(std::exchange(other.model_, nullptr)), scaling_(other.scaling_), report_(std::move(other.report_)) {}

ContactSvm& ContactSvm::operator=(ContactSvm&& other) noexcept {
    if (this != &other) {
        svm_free_and_destroy_model(&model_);
        model_ = std::exchange(other.model_, nullptr);
        scaling_ = other.scaling_;
        report_ = std::move(other.report_);
    }
    return *this;
}

ContactSvm::~ContactSvm() { svm_free_and_destroy_model(&model_); }

double ContactSvm::decision(float speed, float height) const {
    if (!model_) return -1.0;  // moved-from
    return decisionValue(model_, keyToFeature(featureKey(scaling_, speed, height)));
}

bool ContactSvm::predict(float speed, float height) const { return decision(speed, height) > 0.0; }

FootContacts ContactSvm::classify(const MotionSignals& signals) const {
    FootContacts out;
    for (const Foot foot : {Foot::Left, Foot::Right}) {
        const auto side = static_cast<std::size_t>(foot);
        const auto& speed = signals.footSpeed[side];
        const auto& height = signals.footHeight[side];
        auto& c = out.foot(foot);
        c.assign(std::min(speed.size(), height.size()), 0);
        // Each frame is independent; the result does not depend on the split.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, c.size(), 256), [&](const auto& range) {
            for (std::size_t f = range.begin(); f != range.end(); ++f) c[f] = predict(speed[f], height[f]) ? 1 : 0;
        });
    }
    return out;
}

Result<ContactSvm> ContactSvm::train(const std::vector<TrainingSample>& samples, const SvmTrainOptions& options,
                                     const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    silenceLibsvm();
    auto prepared = prepare(samples, options);
    if (!prepared) return prepared.error();
    if (const Status grid = checkGrid(options); !grid) return grid.error();
    const TrainingSet& set = *prepared;

    struct Cell {
        double log2C;
        double log2Gamma;
    };
    std::vector<Cell> cells;
    for (const double c : options.log2C)
        for (const double g : options.log2Gamma) cells.push_back({c, g});

    // Cells in parallel (and each cell's retrainings too: TBB balances the
    // nested loops). The callback is serialised; its fraction only grows.
    constexpr std::string_view kStage = "contact SVM grid search";
    std::atomic<bool> cancelled{!reportProgress(progress, 0.0, kStage)};
    std::mutex progressMutex;
    std::size_t done = 0;
    std::vector<CellResult> results(cells.size());
    if (!cancelled) {
        tbb::parallel_for(std::size_t{0}, cells.size(), [&](std::size_t c) {
            if (cancelled.load(std::memory_order_relaxed)) return;
            results[c] = evaluateCell(set, std::exp2(cells[c].log2C), std::exp2(cells[c].log2Gamma), options.eps,
                                      LooMethod::Shortcut, cancelled);
            const std::lock_guard lock(progressMutex);
            ++done;
            const double fraction = static_cast<double>(done) / static_cast<double>(cells.size());
            if (!cancelled && !reportProgress(progress, fraction, kStage)) cancelled = true;
        });
    }
    if (cancelled) return fray::cancelled();

    // Best cell: the most correct leave-one-out predictions; ties go to the
    // smaller C, then the smaller gamma (the smoother boundary).
    std::size_t best = 0;
    for (std::size_t c = 1; c < cells.size(); ++c) {
        const long long a = results[c].correct;
        const long long b = results[best].correct;
        const bool better = a != b                                  ? a > b
                            : cells[c].log2C != cells[best].log2C   ? cells[c].log2C < cells[best].log2C
                                                                    : cells[c].log2Gamma < cells[best].log2Gamma;
        if (better) best = c;
    }
    if (results[best].model.sv.empty()) return makeError("libsvm failed to train the contact SVM");

    const auto samplesUsed = static_cast<double>(set.samples);
    SvmReport report;
    report.C = std::exp2(cells[best].log2C);
    report.gamma = std::exp2(cells[best].log2Gamma);
    report.looAccuracy = static_cast<double>(results[best].correct) / samplesUsed;
    report.samples = set.samples;
    report.distinctSamples = static_cast<int>(set.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const double loo = static_cast<double>(results[c].correct) / samplesUsed;
        report.grid.push_back({cells[c].log2C, cells[c].log2Gamma, loo});
        report.looRetrains += results[c].retrains;
    }
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return ContactSvmAccess::make(results[best].model, set.scaling, std::move(report));
}

Result<SvmGridCell> evaluateSvmCell(const std::vector<TrainingSample>& samples, double log2C, double log2Gamma,
                                    LooMethod method, const SvmTrainOptions& options) {
    silenceLibsvm();
    auto prepared = prepare(samples, options);
    if (!prepared) return prepared.error();
    SvmTrainOptions one;
    one.log2C = {log2C};
    one.log2Gamma = {log2Gamma};
    if (const Status grid = checkGrid(one); !grid) return grid.error();
    const std::atomic<bool> notCancelled{false};
    const CellResult r =
        evaluateCell(*prepared, std::exp2(log2C), std::exp2(log2Gamma), options.eps, method, notCancelled);
    return SvmGridCell{log2C, log2Gamma, static_cast<double>(r.correct) / prepared->samples};
}

std::vector<std::uint8_t> ContactSvm::serialize() const {
    std::vector<std::uint8_t> out;
    if (!model_) return out;
    const SvmData d = ContactSvmAccess::data(*this);
    out.reserve(kHeaderBytes + kSvBytes * d.sv.size());
    out.insert(out.end(), std::begin(kMagic), std::end(kMagic));
    putU32(out, kVersion);
    for (const double v : {scaling_.speedRef, scaling_.heightRef, scaling_.lo[0], scaling_.hi[0], scaling_.lo[1],
                           scaling_.hi[1], d.C, d.gamma, d.rho, report_.looAccuracy})
        putF64(out, v);
    putU32(out, static_cast<std::uint32_t>(report_.samples));
    putU32(out, static_cast<std::uint32_t>(d.nContact));
    putU32(out, static_cast<std::uint32_t>(d.sv.size()) - static_cast<std::uint32_t>(d.nContact));
    for (std::size_t i = 0; i < d.sv.size(); ++i) {
        putF64(out, d.sv[i][0]);
        putF64(out, d.sv[i][1]);
        putF64(out, d.coef[i]);
    }
    return out;
}

Result<ContactSvm> ContactSvm::deserialize(std::span<const std::uint8_t> bytes) {
    const auto bad = [](const std::string& why) { return makeError("contact SVM data is invalid: " + why); };
    if (bytes.size() < kHeaderBytes)
        return bad(std::to_string(bytes.size()) + " bytes, the header alone is " + std::to_string(kHeaderBytes));
    if (!std::equal(std::begin(kMagic), std::end(kMagic), bytes.begin())) return bad("not a contact SVM (bad magic)");
    Reader r{bytes, 4};
    std::uint32_t version = 0;
    (void)r.u32(version);
    if (version != kVersion) return bad("unsupported version " + std::to_string(version));

    Scaling s;
    SvmData d;
    double loo = 0;
    std::uint32_t samples = 0;
    std::uint32_t nContact = 0;
    std::uint32_t nFree = 0;
    for (double* v :
         {&s.speedRef, &s.heightRef, &s.lo[0], &s.hi[0], &s.lo[1], &s.hi[1], &d.C, &d.gamma, &d.rho, &loo}) {
        (void)r.f64(*v);
        if (!std::isfinite(*v)) return bad("non-finite header value");
    }
    (void)r.u32(samples);
    (void)r.u32(nContact);
    (void)r.u32(nFree);
    if (!(s.speedRef > 0) || !(s.heightRef > 0) || !(s.hi[0] > s.lo[0]) || !(s.hi[1] > s.lo[1]))
        return bad("feature scaling out of range");
    if (!(d.C > 0) || !(d.gamma > 0)) return bad("C and gamma must be positive");
    if (loo < 0 || loo > 1) return bad("leave-one-out accuracy outside [0, 1]");
    if (samples > static_cast<std::uint32_t>(INT32_MAX)) return bad("sample count out of range");
    if (nContact == 0 || nFree == 0 || nContact > kMaxSvPerClass || nFree > kMaxSvPerClass)
        return bad("support vector counts " + std::to_string(nContact) + "/" + std::to_string(nFree) +
                   " out of range");
    const std::size_t total = std::size_t{nContact} + nFree;
    if (bytes.size() != kHeaderBytes + kSvBytes * total)
        return bad(std::to_string(bytes.size()) + " bytes, expected " +
                   std::to_string(kHeaderBytes + kSvBytes * total) + " for " + std::to_string(total) +
                   " support vectors");
    d.nContact = static_cast<int>(nContact);
    d.sv.resize(total);
    d.coef.resize(total);
    for (std::size_t i = 0; i < total; ++i) {
        (void)r.f64(d.sv[i][0]);
        (void)r.f64(d.sv[i][1]);
        (void)r.f64(d.coef[i]);
        // Scaled features live in [0, 1]; coefficients are y_i alpha_i with 0 < alpha_i <= C.
        const bool inside = d.sv[i][0] >= 0 && d.sv[i][0] <= 1 && d.sv[i][1] >= 0 && d.sv[i][1] <= 1;
        const double signedCoef = i < nContact ? d.coef[i] : -d.coef[i];
        if (!inside || !(signedCoef > 0) || !(signedCoef <= d.C * (1 + 1e-9)))
            return bad("support vector " + std::to_string(i) + " out of range");
    }
    SvmReport report;
    report.C = d.C;
    report.gamma = d.gamma;
    report.looAccuracy = loo;
    report.samples = static_cast<int>(samples);
    return ContactSvmAccess::make(d, s, std::move(report));
}

}  // namespace fray::prep
