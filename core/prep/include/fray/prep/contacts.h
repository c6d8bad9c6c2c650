#pragma once
// Supporting-foot classification (SPEC 1.3). Per foot and per frame the
// feature is (foot speed, foot height) from MotionSignals; a soft-margin SVM
// with an RBF kernel, its C and gamma picked by a grid search scored with
// leave-one-out cross-validation, labels every frame from ~20 s of user
// labels. A threshold heuristic is the fallback for motions with no labels.
#include <cstdint>
#include <span>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/prep/labels.h"
#include "fray/prep/signals.h"

struct svm_model;  // libsvm; kept out of this header

namespace fray::prep {

// ---- Heuristic fallback -------------------------------------------------

// A foot supports when it is low and slow; a median filter then removes
// single-frame flickers. This is the simple rule motion-matching systems use
// to mark contacts in their databases. The defaults suit real captures
// (jittery feet, toes a few cm above the floor level while planted).
struct HeuristicParams {
    float maxHeight = 0.05f;  // m above the foot's floor level (MotionSignals::footHeight)
    float maxSpeed = 0.3f;    // m/s
    int medianWindow = 5;     // frames at 60 fps, scaled to the motion's rate (kept odd); <= 1 disables it
};

FootContacts heuristicContacts(const MotionSignals& signals, const HeuristicParams& params = {});

// ---- SVM ----------------------------------------------------------------

struct TrainingSample {
    float speed = 0.0f;   // m/s
    float height = 0.0f;  // m
    bool contact = false;
};

// The labelled frames of one motion: the left foot's frames first, then the
// right foot's, each in frame order (so an even stride through the result is
// a temporal subsampling of both feet). Frames past either array are ignored.
std::vector<TrainingSample> collectSamples(const MotionSignals& signals, const FrameLabels& labels);

// Leave-one-out accuracy, as train() scores it. Samples with the same
// quantised feature and label are one training row (planted feet repeat one
// point hundreds of times); a row is left out whole and counts as many
// samples as it holds.
struct SvmGridCell {
    double log2C = 0.0;
    double log2Gamma = 0.0;
    double looAccuracy = 0.0;
};

struct SvmTrainOptions {
    // Grid of quantised values (powers of two). The features are scaled to
    // [0, 1] inside the model, so these ranges hold for any capture.
    std::vector<double> log2C = {1, 3, 5, 7, 9};
    std::vector<double> log2Gamma = {-1, 1, 3, 5, 7};
    // With more samples than this, an even temporal stride keeps this many
    // (neighbouring frames at 60 fps carry almost the same feature). The
    // default is 20 s of labels at 60 fps, both feet.
    int maxSamples = 2400;
    double eps = 1e-3;  // libsvm stopping tolerance
};

struct SvmReport {
    double C = 0;
    double gamma = 0;
    double looAccuracy = 0;
    int samples = 0;  // samples scored (after subsampling)
    int supportVectors = 0;
    std::vector<SvmGridCell> grid;  // every cell, log2C-major in the options' order
    double seconds = 0;             // wall time of train()
    // Training rows: samples with the same quantised feature and label are
    // one row (0 after deserialize).
    int distinctSamples = 0;
    // Cost of the leave-one-out shortcut over the whole grid: rows that
    // needed a retraining (brute force retrains every row of every cell).
    long long looRetrains = 0;
};

// How a grid cell's leave-one-out accuracy is computed. Both give the same
// value (within libsvm's tolerance); BruteForce exists to test that.
enum class LooMethod { Shortcut, BruteForce };

// The leave-one-out accuracy train() gives one (C, gamma) cell, on the same
// prepared (subsampled, scaled, de-duplicated) training set.
Result<SvmGridCell> evaluateSvmCell(const std::vector<TrainingSample>& samples, double log2C, double log2Gamma,
                                    LooMethod method = LooMethod::Shortcut, const SvmTrainOptions& options = {});

// A trained classifier: libsvm's model plus the feature scaling it was
// trained with. Move-only; owns the model.
class ContactSvm {
public:
    ContactSvm(ContactSvm&& other) noexcept;
    ContactSvm& operator=(ContactSvm&& other) noexcept;
    ContactSvm(const ContactSvm&) = delete;
    ContactSvm& operator=(const ContactSvm&) = delete;
    ~ContactSvm();

    // Grid search over (C, gamma) by leave-one-out accuracy; the best cell's
    // model is kept. Ties go to the smaller C, then the smaller gamma (the
    // smoother boundary). Deterministic. progress gets the fraction of grid
    // cells done (called from worker threads, one call at a time); returning
    // false cancels with Error "cancelled".
    static Result<ContactSvm> train(const std::vector<TrainingSample>& samples, const SvmTrainOptions& options = {},
                                    const ProgressFn& progress = {});

    // Every frame, both feet.
    FootContacts classify(const MotionSignals& signals) const;
    bool predict(float speed, float height) const;
    // Signed distance-like value: > 0 means supporting.
    double decision(float speed, float height) const;
    const SvmReport& report() const { return report_; }

    // Compact little-endian binary: scaling, C, gamma, support vectors,
    // coefficients, rho. Classification after deserialize is identical.
    std::vector<std::uint8_t> serialize() const;
    // Validates every size and value; garbage gives an Error, never a crash.
    static Result<ContactSvm> deserialize(std::span<const std::uint8_t> bytes);

    // Feature scaling (public so tests and tools can inspect it): each
    // feature is log-compressed, log2(1 + max(0, v) / ref), then mapped from
    // [lo, hi] (the training range) to [0, 1], clamped and rounded to 1/4096.
    // The log makes the kernel width a ratio: the boundary lies at a few cm
    // and cm/s for a real capture (less for the demo actor), while free feet
    // reach metres and m/s, and one gamma has to fit all of them.
    struct Scaling {
        double speedRef = 0.02;    // m/s
        double heightRef = 0.005;  // m
        double lo[2] = {0, 0};
        double hi[2] = {1, 1};
    };
    const Scaling& scaling() const { return scaling_; }

private:
    ContactSvm() = default;
    svm_model* model_ = nullptr;
    Scaling scaling_;
    SvmReport report_;
    friend struct ContactSvmAccess;
};

// The contacts over [firstFrame, lastFrame] as label ranges: one range per
// run of frames where neither foot changes (clamped to the contacts' frames).
// Turns known or reviewed contacts into labels (SVM training data, a CSV).
std::vector<ContactLabel> labelsFromContacts(const FootContacts& contacts, int firstFrame, int lastFrame);

// Fraction of (frame, foot) pairs on which a and b agree; frames only one of
// them has count as disagreements. 1 when both are empty.
double contactAgreement(const FootContacts& a, const FootContacts& b);

}  // namespace fray::prep
