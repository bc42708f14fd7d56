#include "core/error.h"

#include <fstream>

namespace ml {

std::string FileLoc::to_string() const {
    if (file.empty()) return "<input>";
    if (line <= 0) return file;
    if (column <= 0) return fmt::format("{}:{}", file, line);
    return fmt::format("{}:{}:{}", file, line, column);
}

namespace {

std::string located(const std::string& message, const std::source_location& where) {
    return fmt::format("{}:{}: internal error: {}", where.file_name(), where.line(), message);
}

}  // namespace

InternalError::InternalError(const std::string& message, std::source_location where)
    : Error(located(message, where)) {}

std::string InputError::formatted() const {
    std::string out = fmt::format("{}: {}", m_loc.to_string(), what());
    if (m_loc.file.empty() || m_loc.line <= 0) return out;
    std::ifstream in(m_loc.file, std::ios::binary);
    if (!in) return out;
    // Only text files get their line shown: a binary mesh has no useful line.
    std::string text;
    for (int i = 0; i < m_loc.line && std::getline(in, text); ++i) {
    }
    if (!in && !in.eof()) return out;
    if (text.size() > 200) return out;
    for (char c : text)
        if ((unsigned char)c < 9 || (unsigned char)c == 0x7f) return out;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    out += "\n" + text;
    if (m_loc.column > 0 && m_loc.column <= int(text.size()) + 1) {
        std::string caret;
        for (int i = 0; i < m_loc.column - 1; ++i) caret += text[i] == '\t' ? '\t' : ' ';
        out += "\n" + caret + "^";
    }
    return out;
}

}  // namespace ml
