// Text as brdffit writes it where it must not be read as anything else: for terminals
// (printable, error.h), HTML and XML (escape_markup, io.h; xml_text and the rest, text.h, with
// xml_unescape, the reverse for the XML brdffit reads),
// Markdown and CSV (io.h), and the UTF-8 checks they rest on. One module, so that each sink
// has one escaping and a fix reaches every caller.
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <string>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/text.h"

namespace brdffit {

size_t utf8_sequence_length(const std::string& text, size_t i) {
  const auto byte = [&](size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
  const unsigned lead = byte(i);
  const auto continuation = [&](size_t k, unsigned low = 0x80, unsigned high = 0xBF) {
    return byte(k) >= low && byte(k) <= high;
  };
  if (lead < 0x80) return 1;
  if (lead >= 0xC2 && lead <= 0xDF) return continuation(i + 1) ? 2 : 0;
  if (lead >= 0xE0 && lead <= 0xEF) {
    // E0: no overlong forms; ED: no surrogates (U+D800..U+DFFF).
    const unsigned low = lead == 0xE0 ? 0xA0 : 0x80, high = lead == 0xED ? 0x9F : 0xBF;
    return continuation(i + 1, low, high) && continuation(i + 2) ? 3 : 0;
  }
  if (lead >= 0xF0 && lead <= 0xF4) {
    // F0: no overlong forms; F4: nothing above U+10FFFF.
    const unsigned low = lead == 0xF0 ? 0x90 : 0x80, high = lead == 0xF4 ? 0x8F : 0xBF;
    return continuation(i + 1, low, high) && continuation(i + 2) && continuation(i + 3) ? 4 : 0;
  }
  return 0;  // a continuation byte, C0, C1 or F5..FF
}

bool valid_utf8(const std::string& text) {
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_sequence_length(text, i);
    if (length == 0) return false;
    i += length;
  }
  return true;
}

std::string printable(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_sequence_length(text, i);
    const unsigned char c = static_cast<unsigned char>(text[i]);
    // C1 controls (U+0080..U+009F, C2 80..C2 9F) act as escape sequences on some terminals too.
    const bool c1 = length == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
    if (length == 0 || c < 0x20 || c == 0x7F || c1) {
      if (c == '\n' || c == '\t')
        out += static_cast<char>(c);
      else
        out += fmt::format("\\x{:02x}", c);
      i += 1;
      if (c1) out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[i++]));
      continue;
    }
    out.append(text, i, length);
    i += length;
  }
  return out;
}

std::string escape_markup(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char ch : text) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

std::string escape_markdown(const std::string& text) {
  std::string out;
  for (const char c : escape_markup(text)) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      out += ' ';
    else if (std::strchr("\\`*_[]|", c))
      out += std::string("\\") + c;
    else
      out += c;
  }
  return out;
}

// Characters that can stand in XML 1.0 text: escaped markup, and every byte that is not part of
// well-formed UTF-8, is a control character other than tab and newline, DEL, or part of U+FFFE or
// U+FFFF (EF BF BE, EF BF BF: not XML characters) written as "\xNN".
std::string xml_text(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const size_t length = utf8_sequence_length(text, i);
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[i + k]); };
    const bool control = length == 1 && ((byte(0) < 0x20 && byte(0) != '\t' && byte(0) != '\n') || byte(0) == 0x7F);
    const bool non_character = length == 3 && byte(0) == 0xEF && byte(1) == 0xBF && byte(2) >= 0xBE;
    if (length == 0 || control || non_character) {
      for (size_t k = 0; k < std::max<size_t>(length, 1); ++k) out += fmt::format("\\x{:02X}", byte(k));
      i += std::max<size_t>(length, 1);
    } else {
      out += length == 1 ? escape_markup(text.substr(i, 1)) : text.substr(i, length);
      i += length;
    }
  }
  return out;
}

// Text inside an XML comment: as xml_text, and no "--" (which would end it).
std::string xml_comment_text(const std::string& text) {
  std::string out;
  for (char c : xml_text(text)) out += c == '-' && !out.empty() && out.back() == '-' ? " -" : std::string(1, c);
  return out;
}

// Entities and character references replaced (text.h).
std::string xml_unescape(const std::string& text, const std::string& path) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      out += text[i];
      continue;
    }
    const size_t end = text.find(';', i);
    if (end == std::string::npos) fail("{}: malformed XML: '&' without ';'", path);
    const std::string entity = text.substr(i + 1, end - i - 1);
    if (entity == "amp")
      out += '&';
    else if (entity == "lt")
      out += '<';
    else if (entity == "gt")
      out += '>';
    else if (entity == "quot")
      out += '"';
    else if (entity == "apos")
      out += '\'';
    else if (entity.size() > 1 && entity[0] == '#') {
      const bool hex = entity[1] == 'x' || entity[1] == 'X';
      const long code = std::strtol(entity.c_str() + (hex ? 2 : 1), nullptr, hex ? 16 : 10);
      if (code > 0 && code < 0x80)
        out += static_cast<char>(code);
      else
        out += '?';  // names and numbers here are ASCII
    } else {
      fail("{}: malformed XML: unknown entity &{};", path, entity);
    }
    i = end;
  }
  return out;
}

// A name for an XML id or a MaterialX element: letters, digits and '_' only, not starting with a digit.
std::string xml_name(const std::string& name) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return id.empty() || std::isdigit(static_cast<unsigned char>(id[0])) ? "m_" + id : id;
}

}  // namespace brdffit
