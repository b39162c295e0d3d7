#pragma once
// Typed, located access to a JSON object of a scene spec. Every read marks its key as used;
// finish() turns keys nobody read into errors, so a typo ("fov_degs") is never silently
// ignored (the habit of pbrt's paramdict and Mitsuba's Properties).
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace tc {

class SpecReader {
public:
    // `file` and `path` locate the object in messages: "scene.json: render.kbuffer.k: ...".
    // Keys listed in `overridden` (full key paths) came from --set and are located as such.
    SpecReader(const nlohmann::json& object, std::string file, std::string path,
               const std::set<std::string>* overridden = nullptr);

    bool has(const std::string& key) const;
    const nlohmann::json& raw(const std::string& key);  // marks used; the key must exist
    SpecReader child(const std::string& key);           // the key must hold an object

    bool getBool(const std::string& key, bool fallback);
    int getInt(const std::string& key, int fallback, int lo, int hi);
    float getFloat(const std::string& key, float fallback, float lo, float hi);
    std::string getString(const std::string& key, const std::string& fallback);
    std::string getEnum(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
    glm::vec3 getVec3(const std::string& key, glm::vec3 fallback);
    glm::vec4 getVec4(const std::string& key, glm::vec4 fallback);
    // An array of 3 or 4 numbers in [0,1]; 3 numbers get alpha = 1.
    glm::vec4 getColor(const std::string& key, glm::vec4 fallback);
    std::vector<std::string> getStringList(const std::string& key, const std::vector<std::string>& fallback,
                                           const std::vector<std::string>& allowed);

    // Throws for keys of this object nobody read.
    void finish() const;

    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    std::string location(const std::string& key) const;  // "file: path.key"
    const std::string& file() const { return m_file; }
    std::string keyPath(const std::string& key) const;

private:
    const nlohmann::json& m_object;
    std::string m_file;
    std::string m_path;
    const std::set<std::string>* m_overridden;
    std::set<std::string> m_used;
    mutable std::set<std::string> m_known;  // every key asked for: suggestions for typos
};

// A JSON value for messages: short, on one line.
std::string describeJson(const nlohmann::json& value);

}  // namespace tc
