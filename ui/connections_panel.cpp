#include "connections_panel.h"

#include <QCheckBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QTableWidget>
#include <QVBoxLayout>

namespace vssim {

ConnectionsPanel::ConnectionsPanel(QWidget* parent)
    : QWidget(parent),
      listening_(new QLabel(this)),
      table_(new QTableWidget(0, ColumnCount, this)),
      firasim_(new QCheckBox(tr("FIRASim interface"), this)),
      firasimStatus_(new QLabel(this)) {
    firasim_->setObjectName(QStringLiteral("connections.firasim"));
    firasim_->setToolTip(tr("Commands and replacement over UDP, vision to 224.0.0.1:10002 (docs/firasim.md)"));
    firasimStatus_->setObjectName(QStringLiteral("connections.firasimStatus"));
    connect(firasim_, &QCheckBox::toggled, this, &ConnectionsPanel::firasimToggled);
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
    auto* fira = new QHBoxLayout;
    fira->addWidget(firasim_);
    fira->addWidget(firasimStatus_, 1);
    layout->addLayout(fira);
    layout->addWidget(table_);
    setListening(tr("not listening"));
    showFirasimOff();
}

void ConnectionsPanel::setListening(const QString& text) { listening_->setText(tr("Listening on %1").arg(text)); }

void ConnectionsPanel::showFirasim(const FirasimServer& server) {
    const QSignalBlocker block(firasim_);
    firasim_->setChecked(true);
    const FirasimSettings& s = server.settings();
    const FirasimStats& st = server.stats();
    firasimStatus_->setText(tr("commands on %1:%2, vision to %3:%4 (%5); %6 packets, %7 vision sent, %8 errors")
                                .arg(server.address().toString())
                                .arg(server.port())
                                .arg(s.visionAddress.toString())
                                .arg(s.visionPort)
                                .arg(server.multicast() ? tr("multicast") : tr("unicast"))
                                .arg(st.datagrams)
                                .arg(st.visionSent)
                                .arg(st.errors() + st.sendErrors));
}

void ConnectionsPanel::showFirasimOff(const QString& why) {
    const QSignalBlocker block(firasim_);
    firasim_->setChecked(false);
    firasimStatus_->setText(why.isEmpty() ? tr("off") : tr("off: %1").arg(why));
}

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
