// Text from outside (scene files, clients) made safe to show in a message.
#pragma once

#include <QString>

namespace vssim {

// `text` with every character that is not printable (newlines, ESC, other
// control and format characters such as U+202E, the line and paragraph
// separators U+2028 and U+2029) as "?", and cut to `maxCharacters`
// characters (code points) with "..." after: safe for log lines and error
// messages.
QString printableText(const QString& text, int maxCharacters);

}  // namespace vssim
