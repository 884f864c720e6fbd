// A small reader of XML elements and attributes (xml_reader.h).
#include "brdffit/xml_reader.h"

#include "brdffit/error.h"
#include "brdffit/text.h"

namespace brdffit {

std::vector<XmlElement> parse_xml(const std::string& text, const std::string& path) {
  std::vector<XmlElement> elements;
  std::vector<int> open;
  size_t i = 0;
  const auto malformed = [&](const char* what) { fail("{}: malformed XML: {} (at byte {})", path, what, i); };
  while ((i = text.find('<', i)) != std::string::npos) {
    if (text.compare(i, 4, "<!--") == 0) {
      const size_t end = text.find("-->", i + 4);
      if (end == std::string::npos) malformed("unterminated comment");
      i = end + 3;
      continue;
    }
    if (text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      const size_t end = text.find('>', i);
      if (end == std::string::npos) malformed("unterminated declaration");
      i = end + 1;
      continue;
    }
    const size_t end = text.find('>', i);
    if (end == std::string::npos) malformed("unterminated tag");
    std::string body = text.substr(i + 1, end - i - 1);
    if (!body.empty() && body[0] == '/') {
      const std::string tag = body.substr(1, body.find_first_of(" \t\r\n", 1) - 1);
      if (open.empty() || elements[open.back()].tag != tag) malformed("mismatched end tag");
      open.pop_back();
      i = end + 1;
      continue;
    }
    const bool self_closing = !body.empty() && body.back() == '/';
    if (self_closing) body.pop_back();
    XmlElement element;
    size_t k = body.find_first_of(" \t\r\n");
    element.tag = body.substr(0, k);
    if (element.tag.empty()) malformed("empty tag");
    while (k != std::string::npos && k < body.size()) {
      k = body.find_first_not_of(" \t\r\n", k);
      if (k == std::string::npos) break;
      const size_t eq = body.find('=', k);
      if (eq == std::string::npos) malformed("attribute without a value");
      std::string name = body.substr(k, eq - k);
      name.erase(name.find_last_not_of(" \t\r\n") + 1);
      size_t q = body.find_first_not_of(" \t\r\n", eq + 1);
      if (q == std::string::npos || (body[q] != '"' && body[q] != '\'')) malformed("unquoted attribute");
      const size_t close = body.find(body[q], q + 1);
      if (close == std::string::npos) malformed("unterminated attribute");
      element.attributes[name] = xml_unescape(body.substr(q + 1, close - q - 1), path);
      k = close + 1;
    }
    element.parent = open.empty() ? -1 : open.back();
    if (element.parent >= 0) elements[element.parent].children.push_back(static_cast<int>(elements.size()));
    elements.push_back(std::move(element));
    if (!self_closing) open.push_back(static_cast<int>(elements.size()) - 1);
    i = end + 1;
  }
  if (!open.empty()) fail("{}: malformed XML: <{}> is never closed", path, elements[open.back()].tag);
  return elements;
}

std::string attribute(const XmlElement& e, const std::string& name) {
  const auto it = e.attributes.find(name);
  return it == e.attributes.end() ? "" : it->second;
}

}  // namespace brdffit
