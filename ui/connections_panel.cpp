#include "connections_panel.h"

#include <QHeaderView>
#include <QLabel>
#include <QTableWidget>
#include <QVBoxLayout>

namespace vssim {

ConnectionsPanel::ConnectionsPanel(QWidget* parent)
    : QWidget(parent), listening_(new QLabel(this)), table_(new QTableWidget(0, ColumnCount, this)) {
    listening_->setObjectName(QStringLiteral("connections.listening"));
    table_->setObjectName(QStringLiteral("connections.table"));
    table_->setHorizontalHeaderLabels({tr("id"), tr("address"), tr("role"), tr("name"), tr("images"),
                                       tr("commands (1/s)"), tr("frames sent"), tr("frames dropped"),
                                       tr("connected (s)")});
    table_->verticalHeader()->setVisible(false);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->setSelectionMode(QAbstractItemView::NoSelection);
    table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);

    auto* layout = new QVBoxLayout(this);
    layout->addWidget(listening_);
    layout->addWidget(table_);
    setListening(tr("not listening"));
}

void ConnectionsPanel::setListening(const QString& text) { listening_->setText(tr("Listening on %1").arg(text)); }

void ConnectionsPanel::setClients(const std::vector<ClientInfo>& clients, double secondsSinceLast) {
    std::map<int, std::int64_t> counts;
    table_->setRowCount(static_cast<int>(clients.size()));
    for (int row = 0; row < static_cast<int>(clients.size()); ++row) {
        const ClientInfo& c = clients[static_cast<std::size_t>(row)];
        QString rate;
        const auto last = lastCommands_.find(c.id);
        if (last != lastCommands_.end() && secondsSinceLast > 0.0)
            rate = QString::number(static_cast<double>(c.commands - last->second) / secondsSinceLast, 'f', 1);
        counts[c.id] = c.commands;

        const QString cells[ColumnCount] = {
            QString::number(c.id),
            c.peer,
            c.greeted ? c.role : tr("(no HELLO yet)"),
            c.name,
            c.images,
            rate,
            QString::number(c.framesSent),
            QString::number(c.framesDropped),
            QString::number(c.connectedSeconds, 'f', 1),
        };
        for (int col = 0; col < ColumnCount; ++col) {
            auto* item = new QTableWidgetItem(cells[col]);
            if (col == Id || col >= CommandsPerSecond) item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
            table_->setItem(row, col, item);
        }
    }
    lastCommands_ = std::move(counts);
}

}  // namespace vssim
