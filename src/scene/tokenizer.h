// Splits pbrt-v4 scene text into tokens (quoted strings, brackets, bare words such as directive
// names and numbers), skipping whitespace and comments and remembering each token's line and
// column for error messages. Works on the whole file held in memory: scenes with large inline
// meshes are tokenized without per-character stream overhead.
#pragma once

#include <string>
#include <string_view>

#include "core/error.h"

namespace ml {

enum class TokenKind { String, Word, LBracket, RBracket, End };

struct Token {
    TokenKind kind = TokenKind::End;
    std::string_view raw;  // the source text (strings without their quotes)
    std::string decoded;   // a string's value when it held escapes
    bool escaped = false;
    const std::string* file = nullptr;  // the tokenizer's file name, alive while it is
    int line = 0, column = 0;
    std::string_view value() const { return escaped ? std::string_view(decoded) : raw; }
};

class Tokenizer {
public:
    // `file` names the text in error messages.
    Tokenizer(std::string text, std::string file);
    // Reads a whole file; throws InputError at `from` if it cannot be read.
    static Tokenizer from_file(const std::string& path, const FileLoc& from);

    // The next token, or one of kind End at the end of the text.
    Token next();
    static FileLoc loc(const Token& t) {
        return FileLoc{t.file ? *t.file : std::string(), t.line, t.column};
    }
    const std::string& file() const { return m_file; }

private:
    [[noreturn]] void fail(int line, int column, const std::string& message) const;
    std::string m_text;
    std::string m_file;
    size_t m_pos = 0;
    int m_line = 1;
    size_t m_line_start = 0;
};

// Parses a decimal number the way scene files write them ("1", "-0.5", "2e-3", "+4", ".5").
// Returns false for anything else, nan and inf included.
bool parse_number(std::string_view s, double* out);

}  // namespace ml
