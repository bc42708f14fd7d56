#include "scene/tokenizer.h"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ml {

Tokenizer::Tokenizer(std::string text, std::string file)
    : m_text(std::move(text)), m_file(std::move(file)) {}

Tokenizer Tokenizer::from_file(const std::string& path, const FileLoc& from) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw_input_error(from, "cannot read \"{}\": it is a directory", path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw_input_error(from, "cannot open \"{}\"", path);
    std::string text;
    in.seekg(0, std::ios::end);
    std::streamoff size = in.tellg();
    if (size < 0) throw_input_error(from, "cannot read \"{}\"", path);
    text.resize(size_t(size));
    in.seekg(0);
    in.read(text.data(), size);
    if (!in) throw_input_error(from, "cannot read \"{}\"", path);
    return Tokenizer(std::move(text), path);
}

void Tokenizer::fail(int line, int column, const std::string& message) const {
    throw InputError(FileLoc{m_file, line, column}, message);
}

namespace {

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}
// Characters that end a bare word: pbrt words run up to whitespace, a quote, a bracket or '#'.
bool ends_word(char c) { return is_space(c) || c == '"' || c == '[' || c == ']' || c == '#'; }

}  // namespace

Token Tokenizer::next() {
    const size_t n = m_text.size();
    const char* s = m_text.data();
    // Skip whitespace and comments, counting lines.
    while (m_pos < n) {
        char c = s[m_pos];
        if (c == '\n') {
            ++m_pos;
            ++m_line;
            m_line_start = m_pos;
        } else if (is_space(c)) {
            ++m_pos;
        } else if (c == '#') {
            while (m_pos < n && s[m_pos] != '\n') ++m_pos;
        } else {
            break;
        }
    }
    Token t;
    t.file = &m_file;
    t.line = m_line;
    t.column = int(m_pos - m_line_start) + 1;
    if (m_pos >= n) return t;

    char c = s[m_pos];
    if (c == '[' || c == ']') {
        t.kind = c == '[' ? TokenKind::LBracket : TokenKind::RBracket;
        t.raw = std::string_view(s + m_pos, 1);
        ++m_pos;
        return t;
    }
    if (c == '"') {
        t.kind = TokenKind::String;
        size_t start = ++m_pos;
        while (m_pos < n && s[m_pos] != '"') {
            if (s[m_pos] == '\n')
                fail(t.line, t.column, "unterminated string (a newline inside quotes)");
            if (s[m_pos] == '\\') {
                t.escaped = true;
                ++m_pos;  // the escaped character never ends the string
                if (m_pos < n && s[m_pos] == '\n') {
                    fail(t.line, t.column, "unterminated string (a newline inside quotes)");
                }
            }
            ++m_pos;
        }
        if (m_pos >= n) fail(t.line, t.column, "unterminated string");
        t.raw = std::string_view(s + start, m_pos - start);
        ++m_pos;  // closing quote
        if (t.escaped) {
            t.decoded.reserve(t.raw.size());
            for (size_t i = 0; i < t.raw.size(); ++i) {
                char ch = t.raw[i];
                if (ch != '\\') {
                    t.decoded += ch;
                    continue;
                }
                char e = t.raw[++i];
                switch (e) {
                    case 'n':
                        t.decoded += '\n';
                        break;
                    case 't':
                        t.decoded += '\t';
                        break;
                    case 'r':
                        t.decoded += '\r';
                        break;
                    case 'b':
                        t.decoded += '\b';
                        break;
                    case 'f':
                        t.decoded += '\f';
                        break;
                    case '\\':
                        t.decoded += '\\';
                        break;
                    case '"':
                        t.decoded += '"';
                        break;
                    case '\'':
                        t.decoded += '\'';
                        break;
                    default:
                        fail(t.line, t.column + 1 + int(i),
                             fmt::format("unknown escape sequence \"\\{}\" in string", e));
                }
            }
        }
        return t;
    }
    t.kind = TokenKind::Word;
    size_t start = m_pos;
    while (m_pos < n && !ends_word(s[m_pos])) ++m_pos;
    t.raw = std::string_view(s + start, m_pos - start);
    return t;
}

bool parse_number(std::string_view s, double* out) {
    if (s.empty()) return false;
    if (s[0] == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    // from_chars also accepts "nan", "inf" and "infinity"; scene numbers start with a digit, a
    // sign or a point.
    char c = s[0] == '-' && s.size() > 1 ? s[1] : s[0];
    if (!((c >= '0' && c <= '9') || c == '.')) return false;
    double v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return false;
    *out = v;
    return true;
}

}  // namespace ml
