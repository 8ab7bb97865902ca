#pragma once
// Text a message echoes from its input (a path, an XML attribute, an option's argument) made safe to print on a
// terminal: it must neither act on the terminal (an escape sequence, a carriage return) nor break the one line a
// message is (a newline).
#include <string>
#include <string_view>

namespace clr {

// `text` safe to print on a terminal as part of one line: newline, carriage return and tab as \n, \r, \t; other
// C0 and C1 control characters, DEL and bytes that are not well-formed UTF-8 as \xNN; well-formed UTF-8 kept.
std::string terminal_safe(std::string_view text);

}  // namespace clr
