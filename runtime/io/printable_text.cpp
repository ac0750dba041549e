#include "io/printable_text.h"

#include <QList>

namespace vssim {

QString printableText(const QString& text, int maxCharacters) {
    QString out;
    int n = 0;
    for (uint c : text.toUcs4()) {
        if (n++ == maxCharacters) return out + QStringLiteral("...");
        const char32_t cp = static_cast<char32_t>(c);
        // Qt counts the line and paragraph separators as printable, but
        // some viewers end a line there.
        const QChar::Category category = QChar::category(cp);
        const bool printable =
            QChar::isPrint(cp) && category != QChar::Separator_Line && category != QChar::Separator_Paragraph;
        out += printable ? QString::fromUcs4(&cp, 1) : QStringLiteral("?");
    }
    return out;
}

}  // namespace vssim
