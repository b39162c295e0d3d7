#include "io/particle_reader_elements.h"

#include <algorithm>
#include <cctype>
#include <unordered_map>

namespace tc {

namespace {

std::string upper(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    return s;
}

glm::vec3 rgb(int r, int g, int b) {
    return glm::vec3(float(r), float(g), float(b)) / 255.0f;
}

const std::unordered_map<std::string, ElementStyle>& table() {
    static const std::unordered_map<std::string, ElementStyle> t = {
        {"H", {1.20f, rgb(255, 255, 255)}},  {"HE", {1.40f, rgb(217, 255, 255)}}, {"LI", {1.82f, rgb(204, 128, 255)}},
        {"B", {1.92f, rgb(255, 181, 181)}},  {"C", {1.70f, rgb(144, 144, 144)}},  {"N", {1.55f, rgb(48, 80, 248)}},
        {"O", {1.52f, rgb(255, 13, 13)}},    {"F", {1.47f, rgb(144, 224, 80)}},   {"NE", {1.54f, rgb(179, 227, 245)}},
        {"NA", {2.27f, rgb(171, 92, 242)}},  {"MG", {1.73f, rgb(138, 255, 0)}},   {"AL", {1.84f, rgb(191, 166, 166)}},
        {"SI", {2.10f, rgb(240, 200, 160)}}, {"P", {1.80f, rgb(255, 128, 0)}},    {"S", {1.80f, rgb(255, 255, 48)}},
        {"CL", {1.75f, rgb(31, 240, 31)}},   {"AR", {1.88f, rgb(128, 209, 227)}}, {"K", {2.75f, rgb(143, 64, 212)}},
        {"CA", {2.31f, rgb(61, 255, 0)}},    {"FE", {2.04f, rgb(224, 102, 51)}},  {"CU", {1.40f, rgb(200, 128, 51)}},
        {"ZN", {1.39f, rgb(125, 128, 176)}}, {"SE", {1.90f, rgb(255, 161, 0)}},   {"BR", {1.85f, rgb(166, 41, 41)}},
        {"KR", {2.02f, rgb(92, 184, 209)}},  {"I", {1.98f, rgb(148, 0, 148)}},    {"XE", {2.16f, rgb(66, 158, 176)}},
        {"AU", {1.66f, rgb(255, 209, 35)}},
    };
    return t;
}

}  // namespace

ElementStyle elementStyle(const std::string& symbol, bool* known) {
    const auto& t = table();
    auto it = t.find(upper(symbol));
    if (known) *known = it != t.end();
    if (it != t.end()) return it->second;
    return {1.70f, rgb(255, 20, 147)};
}

std::string elementFromAtomName(const std::string& name, bool ionHint) {
    std::string letters;
    for (char c : name)
        if (std::isalpha(static_cast<unsigned char>(c)))
            letters += char(std::toupper(static_cast<unsigned char>(c)));
        else if (!letters.empty())
            break;
    if (letters.empty()) return "";
    if (ionHint && letters.size() == 2 && name.find_first_of("0123456789") == std::string::npos) {
        bool known = false;
        elementStyle(letters, &known);
        if (known) return letters;
    }
    bool known = false;
    elementStyle(letters.substr(0, 1), &known);
    if (known) return letters.substr(0, 1);
    return letters.size() >= 2 ? letters.substr(0, 2) : letters;
}

}  // namespace tc
