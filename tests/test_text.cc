// The one base64 encoder (base64.h) and the XML escaping of text.cc (text.h) and its reverse,
// against values worked out by hand from RFC 4648 and the XML 1.0 character rules.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "brdffit/base64.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/text.h"

namespace brdffit {
namespace {

std::vector<uint8_t> bytes_of(const std::string& text) { return {text.begin(), text.end()}; }

// RFC 4648 section 10's test vectors: every padding case (none, one '=', two).
TEST(Text, Base64MatchesRfc4648TestVectors) {
  EXPECT_EQ(base64(bytes_of("")), "");
  EXPECT_EQ(base64(bytes_of("f")), "Zg==");
  EXPECT_EQ(base64(bytes_of("fo")), "Zm8=");
  EXPECT_EQ(base64(bytes_of("foo")), "Zm9v");
  EXPECT_EQ(base64(bytes_of("foob")), "Zm9vYg==");
  EXPECT_EQ(base64(bytes_of("fooba")), "Zm9vYmE=");
  EXPECT_EQ(base64(bytes_of("foobar")), "Zm9vYmFy");
}

// The alphabet's ends: 0xFB 0xEF 0xBE is 111110 four times (62: '+'), 0xFF three times 111111
// (63: '/'), zeros 'A'; the standard alphabet, not the URL-safe one ('-', '_').
TEST(Text, Base64UsesTheStandardAlphabetAtItsEnds) {
  EXPECT_EQ(base64({0xFB, 0xEF, 0xBE}), "++++");
  EXPECT_EQ(base64({0xFF, 0xFF, 0xFF}), "////");
  EXPECT_EQ(base64({0x00, 0x00, 0x00, 0xFF}), "AAAA/w==");
}

// Markup escaped, tab and newline kept, other controls, DEL, bytes outside UTF-8 and the
// non-characters U+FFFE/U+FFFF written as \xNN; well-formed multi-byte characters kept.
TEST(Text, XmlTextEscapesMarkupAndEveryByteXmlCannotHold) {
  EXPECT_EQ(xml_text("a<b & \"c\"\t\n"), "a&lt;b &amp; &quot;c&quot;\t\n");
  EXPECT_EQ(xml_text(std::string("\x01x\x7F", 3)), "\\x01x\\x7F");
  EXPECT_EQ(xml_text("caf\xC3\xA9"), "caf\xC3\xA9");
  EXPECT_EQ(xml_text("\xFF"), "\\xFF");
  EXPECT_EQ(xml_text("\xEF\xBF\xBE|\xEF\xBF\xBF"), "\\xEF\\xBF\\xBE|\\xEF\\xBF\\xBF");
}

// A comment never holds "--": each second dash of a run gets a space before it.
TEST(Text, XmlCommentTextBreaksEveryDoubleDash) {
  const std::string comment = xml_comment_text("a--b---c");
  EXPECT_EQ(comment, "a- -b- - -c");
  EXPECT_EQ(comment.find("--"), std::string::npos);
}

TEST(Text, XmlNameKeepsLettersDigitsAndUnderscoresAndNeverStartsWithADigit) {
  EXPECT_EQ(xml_name("gold_paint"), "gold_paint");
  EXPECT_EQ(xml_name("blue-acrylic.v2"), "blue_acrylic_v2");
  EXPECT_EQ(xml_name("1 a"), "m_1_a");
  EXPECT_EQ(xml_name(""), "m_");
}

// The reverse of the escaping, for the XML brdffit reads: the five named entities and
// character references in decimal and hex; a reference outside ASCII is '?'; a lone '&' or an
// unknown entity is an error naming the file.
TEST(Text, XmlUnescapeReplacesEntitiesAndRefusesMalformedOnes) {
  EXPECT_EQ(xml_unescape("a&amp;b&lt;c&gt;&quot;d&quot;&apos;", "f.xml"), "a&b<c>\"d\"'");
  EXPECT_EQ(xml_unescape("&#65;&#x42;&#X43;&#233;", "f.xml"), "ABC?");
  EXPECT_EQ(xml_unescape(xml_text("x<y&z\""), "f.xml"), "x<y&z\"");  // escape_markup's &#39; too
  EXPECT_EQ(xml_unescape(xml_text("it's"), "f.xml"), "it's");
  EXPECT_THROW(xml_unescape("a & b", "f.xml"), Error);
  try {
    xml_unescape("&nbsp;", "f.xml");
    ADD_FAILURE() << "an unknown entity was read";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "f.xml: malformed XML: unknown entity &nbsp;");
  }
}

// Words for a sentence (io.h): "a", "a or b", "a, b or c".
TEST(Text, JoinWordsPutsTheConjunctionBeforeTheLastWord) {
  EXPECT_EQ(join_words({}, "or"), "");
  EXPECT_EQ(join_words({"a"}, "or"), "a");
  EXPECT_EQ(join_words({"a", "b"}, "or"), "a or b");
  EXPECT_EQ(join_words({"a", "b", "c"}, "and"), "a, b and c");
}

}  // namespace
}  // namespace brdffit
