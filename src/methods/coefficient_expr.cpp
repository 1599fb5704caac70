// Recursive-descent evaluation of coefficient expressions (grammar in coefficient_expr.hpp).
#include "methods/coefficient_expr.hpp"

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdio>

namespace dampsym {
namespace {

class Parser {
public:
    explicit Parser(const std::string& text) : s_(text) {}

    long double parse() {
        const long double v = expr();
        skip();
        if (pos_ != s_.size()) error("unexpected '" + std::string(1, s_[pos_]) + "'");
        if (!std::isfinite(v)) error("the value is not a finite number");
        return v;
    }

private:
    [[noreturn]] void error(const std::string& what) const {
        throw CoefficientExprError("expression \"" + one_line(s_, 200) +
                                   "\": " + one_line(what, 200) + " (at character " +
                                   std::to_string(pos_ + 1) + ")");
    }
    // An expression may be megabytes long and hold control characters: the message shows the
    // first max bytes, control characters escaped, and how many more characters there are.
    static std::string one_line(const std::string& text, std::size_t max) {
        std::string out;
        for (std::size_t i = 0; i < text.size(); ++i) {
            if (i == max) {
                std::size_t rest = 0; // UTF-8 continuation bytes are not characters
                for (std::size_t j = i; j < text.size(); ++j)
                    rest += (static_cast<unsigned char>(text[j]) & 0xC0) != 0x80 ? 1 : 0;
                out += "… (" + std::to_string(rest) + " more characters)";
                break;
            }
            const unsigned char c = static_cast<unsigned char>(text[i]);
            if (c < 0x20 || c == 0x7F) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\x%02x", c);
                out += buf;
            } else {
                out += static_cast<char>(c);
            }
        }
        return out;
    }
    void skip() {
        while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t')) ++pos_;
    }
    bool accept(char ch) {
        skip();
        if (pos_ < s_.size() && s_[pos_] == ch) {
            ++pos_;
            return true;
        }
        return false;
    }
    // Nesting bound: a pathological "((((...))))" or "----1" is an error, not a stack overflow.
    struct Depth {
        explicit Depth(Parser& p) : p_(p) {
            if (++p_.depth_ > 200) p_.error("nested more than 200 levels");
        }
        ~Depth() { --p_.depth_; }
        Parser& p_;
    };
    long double expr() {
        long double v = term();
        while (true) {
            if (accept('+'))
                v += term();
            else if (accept('-'))
                v -= term();
            else
                return v;
        }
    }
    long double term() {
        long double v = factor();
        while (true) {
            if (accept('*')) {
                v *= factor();
            } else if (accept('/')) {
                const long double d = factor();
                if (d == 0.0L) error("division by zero");
                v /= d;
            } else {
                return v;
            }
        }
    }
    long double factor() {
        Depth guard(*this);
        skip();
        if (accept('+')) return factor();
        if (accept('-')) return -factor();
        if (accept('(')) {
            const long double v = expr();
            if (!accept(')')) error("missing ')'");
            return v;
        }
        if (s_.compare(pos_, 4, "sqrt") == 0) {
            pos_ += 4;
            if (!accept('(')) error("expected '(' after sqrt");
            const long double v = expr();
            if (!accept(')')) error("missing ')'");
            if (v < 0.0L) error("square root of a negative number");
            return std::sqrt(v);
        }
        return number();
    }
    long double number() {
        const std::size_t start = pos_;
        long double v = 0.0L;
        bool digits = false;
        while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
            v = v * 10.0L + static_cast<long double>(s_[pos_] - '0');
            ++pos_;
            digits = true;
        }
        if (pos_ < s_.size() && s_[pos_] == '.') {
            ++pos_;
            // Decimal fraction: digits / 10^k, both exact in long double for up to 19 digits, so
            // "0.1" is the correctly rounded long double of 1/10 (one division).
            long double num = 0.0L, den = 1.0L;
            bool frac = false;
            while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
                num = num * 10.0L + static_cast<long double>(s_[pos_] - '0');
                den *= 10.0L;
                ++pos_;
                frac = true;
            }
            if (!frac) error("expected digits after '.'");
            if (pos_ - start > 40) error("number longer than 40 characters");
            v += num / den;
            digits = true;
        }
        if (!digits) {
            if (pos_ >= s_.size()) error("unexpected end of expression");
            error("unexpected '" + std::string(1, s_[pos_]) +
                  "' (allowed: numbers, + - * /, parentheses, sqrt)");
        }
        if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E'))
            error("exponents are not part of the grammar (write 1/1000, not 1e-3)");
        return v;
    }

    const std::string& s_;
    std::size_t pos_ = 0;
    int depth_ = 0;
};

} // namespace

long double evaluate_coefficient_expr(const std::string& text) {
    return Parser(text).parse();
}

} // namespace dampsym
