#include "fray/core/joint_guess.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace fray {
namespace {

enum class Side { None, Left, Right };

struct NameParts {
    Side side = Side::None;
    std::string part;  // lower case, side and separators removed
};

std::string lowerAlnum(std::string_view s) {
    std::string out;
    for (char c : s)
        if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == ' ' || c == '-')
            out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    return out;
}

bool startsWith(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }
bool endsWith(std::string_view s, std::string_view p) {
    return s.size() >= p.size() && s.substr(s.size() - p.size()) == p;
}

std::string stripSeparators(std::string_view s) {
    std::string out;
    for (char c : s)
        if (c != '_' && c != '.' && c != ' ' && c != '-') out.push_back(c);
    return out;
}

// Body-part words a one-letter side prefix may be glued to (CMU "lfemur", "rhand").
const std::vector<std::string_view> kGluedParts = {
    "femur", "tibia", "foot", "toes", "toe", "hand", "humerus", "radius", "wrist", "clavicle", "hipjoint",
    "fingers", "thumb", "shoulder", "elbow", "knee", "ankle", "hip", "upleg", "leg", "arm", "forearm", "collar"};

NameParts split(std::string_view raw) {
    std::string s(raw);
    // Drop namespaces ("mixamorig:LeftHand") and rig prefixes ("Bip01 L Hand").
    if (auto c = s.rfind(':'); c != std::string::npos) s = s.substr(c + 1);
    s = lowerAlnum(s);
    for (std::string_view prefix : {"bip01", "bip001", "mixamorig", "character1", "def-", "def_", "neo"})
        if (startsWith(s, prefix)) s = s.substr(prefix.size());
    while (!s.empty() && (s.front() == '_' || s.front() == ' ' || s.front() == '.' || s.front() == '-'))
        s.erase(s.begin());

    NameParts out;
    auto take = [&](Side side, std::string rest) {
        out.side = side;
        out.part = stripSeparators(rest);
    };
    if (startsWith(s, "left")) return take(Side::Left, s.substr(4)), out;
    if (startsWith(s, "right")) return take(Side::Right, s.substr(5)), out;
    for (std::string_view suffix : {"_l", ".l", " l", "-l", "left"})
        if (endsWith(s, suffix)) return take(Side::Left, s.substr(0, s.size() - suffix.size())), out;
    for (std::string_view suffix : {"_r", ".r", " r", "-r", "right"})
        if (endsWith(s, suffix)) return take(Side::Right, s.substr(0, s.size() - suffix.size())), out;
    for (std::string_view prefix : {"l_", "l.", "l ", "l-"})
        if (startsWith(s, prefix)) return take(Side::Left, s.substr(2)), out;
    for (std::string_view prefix : {"r_", "r.", "r ", "r-"})
        if (startsWith(s, prefix)) return take(Side::Right, s.substr(2)), out;
    if (s.size() > 1 && (s[0] == 'l' || s[0] == 'r')) {
        const std::string rest = stripSeparators(s.substr(1));
        for (std::string_view part : kGluedParts)
            if (startsWith(rest, part)) return take(s[0] == 'l' ? Side::Left : Side::Right, rest), out;
    }
    out.part = stripSeparators(s);
    return out;
}

bool isOneOf(const std::string& s, std::initializer_list<std::string_view> words) {
    return std::any_of(words.begin(), words.end(), [&](std::string_view w) { return s == w; });
}

// Path from `from` up to (and excluding) `ancestor`; empty if not an ancestor.
std::vector<int> pathUp(const Skeleton& sk, int from, int ancestor) {
    std::vector<int> path;
    for (int j = from; j >= 0; j = sk.parents[static_cast<std::size_t>(j)]) {
        if (j == ancestor) return path;
        path.push_back(j);
    }
    return {};
}

}  // namespace

std::string StandardJoints::missing() const {
    std::string out;
    auto add = [&](int v, const char* name) {
        if (v >= 0) return;
        if (!out.empty()) out += ", ";
        out += name;
    };
    add(pelvis, "pelvis");
    add(head, "head");
    add(leftHand, "leftHand");
    add(rightHand, "rightHand");
    add(leftFoot, "leftFoot");
    add(rightFoot, "rightFoot");
    add(leftToe, "leftToe");
    add(rightToe, "rightToe");
    return out;
}

StandardJoints guessStandardJoints(const Skeleton& sk) {
    StandardJoints r;
    const int n = sk.jointCount();
    // First match wins for each role, except where a better word is preferred.
    auto set = [](int& slot, int j) {
        if (slot < 0) slot = j;
    };
    int leftWrist = -1, rightWrist = -1, leftLeg = -1, rightLeg = -1, leftArm = -1, rightArm = -1;
    int leftShoulderWord = -1, rightShoulderWord = -1, lowerNeck = -1, rootLike = -1;
    for (int j = 0; j < n; ++j) {
        const NameParts p = split(sk.names[static_cast<std::size_t>(j)]);
        const bool L = p.side == Side::Left;
        const std::string& w = p.part;
        if (p.side == Side::None) {
            if (isOneOf(w, {"hips", "pelvis", "hip"})) set(r.pelvis, j);
            else if (isOneOf(w, {"root", "jointroot"})) set(rootLike, j);
            else if (isOneOf(w, {"head"})) set(r.head, j);
            else if (isOneOf(w, {"neck", "neck1"})) set(r.neck, j);
            else if (isOneOf(w, {"lowerneck"})) set(lowerNeck, j);
            continue;
        }
        int& hand = L ? r.leftHand : r.rightHand;
        int& wrist = L ? leftWrist : rightWrist;
        int& foot = L ? r.leftFoot : r.rightFoot;
        int& toe = L ? r.leftToe : r.rightToe;
        int& knee = L ? r.leftKnee : r.rightKnee;
        int& hip = L ? r.leftHip : r.rightHip;
        int& elbow = L ? r.leftElbow : r.rightElbow;
        int& arm = L ? leftArm : rightArm;
        int& shoulderWord = L ? leftShoulderWord : rightShoulderWord;
        int& leg = L ? leftLeg : rightLeg;
        if (isOneOf(w, {"hand"})) set(hand, j);
        else if (isOneOf(w, {"wrist"})) set(wrist, j);
        else if (isOneOf(w, {"foot", "ankle"})) set(foot, j);
        else if (isOneOf(w, {"toe", "toes", "toebase", "toe0", "ball"})) set(toe, j);
        else if (isOneOf(w, {"knee", "tibia", "shin", "calf", "lowerleg", "shank"})) set(knee, j);
        else if (isOneOf(w, {"leg"})) set(leg, j);
        else if (isOneOf(w, {"upleg", "upperleg", "thigh", "femur", "hip"})) set(hip, j);
        else if (isOneOf(w, {"forearm", "lowerarm", "elbow", "radius"})) set(elbow, j);
        else if (isOneOf(w, {"arm", "upperarm", "humerus"})) set(arm, j);
        else if (isOneOf(w, {"shoulder"})) set(shoulderWord, j);
    }
    if (r.pelvis < 0) r.pelvis = rootLike >= 0 && !sk.children(rootLike).empty() ? rootLike : 0;
    if (r.neck < 0) r.neck = lowerNeck;
    for (int side = 0; side < 2; ++side) {
        int& hand = side ? r.rightHand : r.leftHand;
        int& elbow = side ? r.rightElbow : r.leftElbow;
        int& shoulder = side ? r.rightShoulder : r.leftShoulder;
        int& knee = side ? r.rightKnee : r.leftKnee;
        int& hip = side ? r.rightHip : r.leftHip;
        int& foot = side ? r.rightFoot : r.leftFoot;
        const int wrist = side ? rightWrist : leftWrist;
        const int arm = side ? rightArm : leftArm;
        const int shoulderWord = side ? rightShoulderWord : leftShoulderWord;
        const int leg = side ? rightLeg : leftLeg;
        if (hand < 0) hand = wrist;
        // "Leg" is the shin when an upper-leg word exists (LAFAN1, Mixamo), else the thigh.
        if (knee < 0 && leg >= 0 && hip >= 0) knee = leg;
        if (hip < 0 && leg >= 0 && knee >= 0 && knee != leg) hip = leg;
        // "Shoulder" is the upper arm unless an arm word exists (then it is the clavicle).
        shoulder = arm >= 0 ? arm : shoulderWord;
        // Structural fallbacks along the chain above the end effector.
        if (elbow < 0 && hand >= 0 && shoulder >= 0) {
            const auto path = pathUp(sk, hand, shoulder);
            if (!path.empty()) elbow = path.back();
        }
        if (knee < 0 && foot >= 0) knee = sk.parents[static_cast<std::size_t>(foot)];
        if (hip < 0 && knee >= 0) hip = sk.parents[static_cast<std::size_t>(knee)];
    }
    // Spine: the joint after the pelvis on the way to the head; chest: below the neck.
    if (r.head >= 0) {
        const auto path = pathUp(sk, r.head, r.pelvis);
        if (!path.empty()) {
            const int top = r.neck >= 0 ? r.neck : r.head;
            r.spine = path.back();
            const auto upper = pathUp(sk, top, r.pelvis);
            if (upper.size() >= 2) r.chest = upper[1];
            if (lowerNeck >= 0 && r.neck >= 0 && r.chest == lowerNeck && upper.size() >= 3) r.chest = upper[2];
        }
    }
    return r;
}

}  // namespace fray
