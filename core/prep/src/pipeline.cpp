#include "fray/prep/pipeline.h"

#include <cstring>

#include "fray/core/atomic_file.h"

namespace fray::prep {
namespace {

constexpr char kMagic[8] = {'F', 'R', 'A', 'Y', 'C', 'A', 'C', 'H'};

class Writer {
public:
    template <class T>
    void put(T v) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void putString(const std::string& s) {
        put(static_cast<std::uint32_t>(s.size()));
        bytes.insert(bytes.end(), s.begin(), s.end());
    }
    std::vector<std::uint8_t> bytes;
};

class ByteReader {
public:
    explicit ByteReader(const std::vector<std::uint8_t>& b) : bytes_(b) {}
    template <class T>
    bool get(T& v) {
        if (bytes_.size() - pos_ < sizeof(T)) return false;
        std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        return true;
    }
    bool getBytes(std::vector<std::uint8_t>& out, std::size_t n) {
        if (bytes_.size() - pos_ < n) return false;
        out.assign(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_),
                   bytes_.begin() + static_cast<std::ptrdiff_t>(pos_ + n));
        pos_ += n;
        return true;
    }
    bool getString(std::string& s) {
        std::uint32_t n = 0;
        if (!get(n) || bytes_.size() - pos_ < n) return false;
        s.assign(reinterpret_cast<const char*>(bytes_.data() + pos_), n);
        pos_ += n;
        return true;
    }
    std::size_t remaining() const { return bytes_.size() - pos_; }

private:
    const std::vector<std::uint8_t>& bytes_;
    std::size_t pos_ = 0;
};

}  // namespace

std::uint64_t hashBytes(const void* data, std::size_t size, std::uint64_t seed) {
    std::uint64_t h = seed;
    const auto* p = static_cast<const std::uint8_t*>(data);
    for (std::size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

std::uint64_t hashString(std::string_view s, std::uint64_t seed) {
    const std::uint64_t n = s.size();
    return hashBytes(s.data(), s.size(), hashBytes(&n, sizeof n, seed));
}

SegmentationParams segmentationParams(const ProjectSettings& settings) {
    SegmentationParams p;
    if (settings.segmentThresholdFactor) p.thresholdFactor = *settings.segmentThresholdFactor;
    return p;
}

Result<std::vector<LoadedMotion>> loadProjectMotions(const Project& project, const std::filesystem::path& projectFile,
                                                     const MotionLoader& loader, const ProgressFn& progress) {
    std::vector<LoadedMotion> out;
    const auto total = static_cast<double>(std::max<std::size_t>(1, project.motions.size()));
    for (std::size_t i = 0; i < project.motions.size(); ++i) {
        const ProjectMotion& entry = project.motions[i];
        const std::string where = projectFile.string() + ": /motions/" + std::to_string(i);
        if (!reportProgress(progress, double(i) / total, "load " + entry.id)) return cancelled();
        LoadedMotion m;
        m.id = entry.id;
        m.file = resolveMotionPath(projectFile, entry);
        std::error_code ec;
        if (!std::filesystem::exists(m.file, ec)) {
            return makeError(where + "/path: motion file '" + m.file.string() + "' does not exist (motion \"" +
                             entry.id + "\"; fix the path or remove the motion)");
        }
        if (!std::filesystem::is_regular_file(m.file, ec)) {
            return makeError(where + "/path: '" + m.file.string() + "' is not a regular file (a folder, device or pipe; motion \"" +
                             entry.id + "\")");
        }
        auto motion = loader(m.file, entry);
        if (!motion) return makeError(where + "/path: " + motion.error().message);
        m.motion = std::move(*motion);
        if (m.motion.frameCount() != entry.actions.frameCount) {
            return makeError(where + "/frame_count: the project says " + std::to_string(entry.actions.frameCount) +
                             " frames but '" + m.file.string() + "' has " +
                             std::to_string(m.motion.frameCount()) + " (the file changed; re-import it)");
        }
        m.joints = guessStandardJoints(m.motion.skeleton());
        auto signals = computeSignals(m.motion, m.joints);
        if (!signals) return makeError(where + ": " + m.file.string() + ": " + signals.error().message);
        m.signals = std::move(*signals);
        const auto size = std::filesystem::file_size(m.file, ec);
        const auto time = std::filesystem::last_write_time(m.file, ec).time_since_epoch().count();
        std::uint64_t key = hashString(entry.path);
        key = hashBytes(&size, sizeof size, key);
        key = hashBytes(&time, sizeof time, key);
        key = hashString(entry.units + "|" + entry.up, key);
        m.fileKey = key;
        out.push_back(std::move(m));
    }
    reportProgress(progress, 1.0, "loaded");
    return out;
}

std::uint64_t trainingKey(const Project& project, const std::vector<LoadedMotion>& motions) {
    std::uint64_t key = hashString("labels");
    for (std::size_t i = 0; i < project.motions.size() && i < motions.size(); ++i) {
        const ProjectMotion& m = project.motions[i];
        if (m.contactLabels.empty()) continue;
        key = hashString(m.id, key);
        key = hashBytes(&motions[i].fileKey, sizeof motions[i].fileKey, key);
        for (const auto& l : m.contactLabels) {
            const int v[4] = {l.firstFrame, l.lastFrame, l.left ? int(*l.left) : -1, l.right ? int(*l.right) : -1};
            key = hashBytes(v, sizeof v, key);
        }
    }
    return key;
}

std::uint64_t contactsKey(const LoadedMotion& motion, std::uint64_t training, bool svm) {
    std::uint64_t key = hashBytes(&motion.fileKey, sizeof motion.fileKey);
    const std::uint8_t s = svm ? 1 : 0;
    key = hashBytes(&s, 1, key);
    return svm ? hashBytes(&training, sizeof training, key) : key;
}

const CachedContacts* DerivedCache::findContacts(const std::string& id, std::uint64_t key) const {
    for (const auto& [cid, c] : contacts) {
        if (cid == id && c.key == key) return &c;
    }
    return nullptr;
}

std::filesystem::path cachePath(const std::filesystem::path& projectFile) {
    std::filesystem::path p = projectFile;
    p += ".cache";
    return p;
}

std::vector<std::uint8_t> serializeCache(const DerivedCache& cache) {
    Writer w;
    w.bytes.insert(w.bytes.end(), std::begin(kMagic), std::end(kMagic));
    w.put(DerivedCache::kVersion);
    w.put(static_cast<std::uint32_t>(cache.contacts.size()));
    for (const auto& [id, c] : cache.contacts) {
        w.putString(id);
        w.put(c.key);
        w.put(static_cast<std::uint8_t>(c.source));
        w.put(static_cast<std::uint32_t>(c.contacts.left.size()));
        w.bytes.insert(w.bytes.end(), c.contacts.left.begin(), c.contacts.left.end());
        w.bytes.insert(w.bytes.end(), c.contacts.right.begin(), c.contacts.right.end());
    }
    w.put(static_cast<std::uint8_t>(cache.graph ? 1 : 0));
    if (cache.graph) {
        w.put(cache.graph->key);
        w.put(static_cast<std::int32_t>(cache.graph->nodeCount));
        w.put(static_cast<std::uint32_t>(cache.graph->startNode.size()));
        for (std::size_t i = 0; i < cache.graph->startNode.size(); ++i) {
            w.put(static_cast<std::int32_t>(cache.graph->startNode[i]));
            w.put(static_cast<std::int32_t>(cache.graph->endNode[i]));
        }
    }
    // Trailer: FNV-1a 64 of every byte before it (magic and version included).
    w.put(hashBytes(w.bytes.data(), w.bytes.size()));
    return std::move(w.bytes);
}

Result<DerivedCache> deserializeCache(const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
        return makeError("not a Fray cache file");
    }
    std::uint32_t version = 0;
    if (bytes.size() < sizeof kMagic + sizeof version) return makeError("truncated cache");
    std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
    if (version != DerivedCache::kVersion) {
        return makeError("cache version " + std::to_string(version) + " is stale (this build writes " +
                         std::to_string(DerivedCache::kVersion) + ")");
    }
    std::uint64_t stored = 0;
    if (bytes.size() < sizeof kMagic + sizeof version + sizeof stored) return makeError("truncated cache");
    const std::size_t checked = bytes.size() - sizeof stored;
    std::memcpy(&stored, bytes.data() + checked, sizeof stored);
    if (hashBytes(bytes.data(), checked) != stored) return makeError("damaged cache (checksum mismatch)");
    std::vector<std::uint8_t> body(bytes.begin() + sizeof kMagic + sizeof version,
                                   bytes.begin() + static_cast<std::ptrdiff_t>(checked));
    ByteReader r(body);
    std::uint32_t count = 0;
    if (!r.get(count)) return makeError("truncated cache");
    DerivedCache cache;
    for (std::uint32_t i = 0; i < count; ++i) {
        std::string id;
        CachedContacts c;
        std::uint8_t source = 0;
        std::uint32_t frames = 0;
        if (!r.getString(id) || !r.get(c.key) || !r.get(source) || !r.get(frames)) return makeError("truncated cache");
        if (source > 1) return makeError("corrupt cache (contact source)");
        if (r.remaining() / 2 < frames) return makeError("truncated cache");
        c.source = static_cast<ContactSource>(source);
        if (!r.getBytes(c.contacts.left, frames) || !r.getBytes(c.contacts.right, frames)) {
            return makeError("truncated cache");
        }
        cache.contacts.emplace_back(std::move(id), std::move(c));
    }
    std::uint8_t hasGraph = 0;
    if (!r.get(hasGraph) || hasGraph > 1) return makeError("corrupt cache (graph flag)");
    if (hasGraph) {
        CachedGraph g;
        std::int32_t nodes = 0;
        std::uint32_t actions = 0;
        if (!r.get(g.key) || !r.get(nodes) || !r.get(actions)) return makeError("truncated cache");
        if (nodes < 0 || r.remaining() / 8 < actions) return makeError("corrupt cache (graph size)");
        g.nodeCount = nodes;
        for (std::uint32_t i = 0; i < actions; ++i) {
            std::int32_t s = 0, e = 0;
            if (!r.get(s) || !r.get(e)) return makeError("truncated cache");
            if (s < 0 || e < 0 || s >= nodes || e >= nodes) return makeError("corrupt cache (graph node)");
            g.startNode.push_back(s);
            g.endNode.push_back(e);
        }
        cache.graph = std::move(g);
    }
    if (r.remaining() != 0) return makeError("corrupt cache (trailing bytes)");
    return cache;
}

DerivedCache readCache(const std::filesystem::path& projectFile, std::string* why, bool* damaged) {
    if (damaged) *damaged = false;
    std::error_code ec;
    if (!std::filesystem::exists(cachePath(projectFile), ec)) {
        if (why) *why = cachePath(projectFile).string() + ": no cache yet";
        return {};
    }
    if (damaged) *damaged = true;
    const auto text = readWholeFile(cachePath(projectFile), "the cache");
    if (!text) {
        if (why) *why = text.error().message;
        return {};
    }
    auto cache = deserializeCache(std::vector<std::uint8_t>(text->begin(), text->end()));
    if (!cache) {
        if (why) *why = cachePath(projectFile).string() + ": " + cache.error().message;
        return {};
    }
    if (damaged) *damaged = false;
    return std::move(*cache);
}

Status writeCache(const std::filesystem::path& projectFile, const DerivedCache& cache) {
    const auto bytes = serializeCache(cache);
    return writeFileAtomically(cachePath(projectFile),
                               std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace fray::prep
