// A small reader of XML elements and attributes (xml_reader.cc): enough for the material files
// brdffit reads (MaterialX, Mitsuba scenes), which keep every value in attributes. Text between
// tags, CDATA and namespaces are not interpreted; comments, declarations and processing
// instructions are skipped.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace brdffit {

struct XmlElement {
  std::string tag;
  std::map<std::string, std::string> attributes;  // unescaped (xml_unescape)
  int parent = -1;                                // index into the element list; -1 for the root
  std::vector<int> children;                      // indices, in document order
};

// Every element of the document in order, with its attributes and parent. Throws Error naming
// `path` for malformed markup (unclosed tags, mismatched end tags, unquoted attributes). Time and
// memory linear in the text's size.
std::vector<XmlElement> parse_xml(const std::string& text, const std::string& path);

// The attribute's value, empty when the element has none.
std::string attribute(const XmlElement& e, const std::string& name);

}  // namespace brdffit
