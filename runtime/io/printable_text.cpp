#include "io/printable_text.h"

#include <QList>

namespace vssim {

QString printableText(const QString& text, int maxCharacters) {
    QString out;
    int n = 0;
    for (uint c : text.toUcs4()) {
        if (n++ == maxCharacters) return out + QStringLiteral("...");
        const char32_t cp = static_cast<char32_t>(c);
        out += QChar::isPrint(cp) ? QString::fromUcs4(&cp, 1) : QStringLiteral("?");
    }
    return out;
}

}  // namespace vssim
