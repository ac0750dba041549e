// The TCP clients of the control server, one table row each, under a
// "Listening on ADDRESS:PORT" line. Fed by the main window from
// ControlServer::clients(); never talks to the server.
#pragma once

#include <QWidget>
#include <map>
#include <vector>

#include "net/control_server.h"

class QLabel;
class QTableWidget;

namespace vssim {

class ConnectionsPanel : public QWidget {
    Q_OBJECT
public:
    // Table columns.
    enum Column {
        Id,
        Address,
        Role,
        Name,
        Images,
        CommandsPerSecond,
        FramesSent,
        FramesDropped,
        ConnectedFor,
        ColumnCount
    };

    explicit ConnectionsPanel(QWidget* parent = nullptr);

    // E.g. "127.0.0.1:10030", or why the server is not listening.
    void setListening(const QString& text);
    // Replaces the rows. Commands per second = (commands now - commands at
    // the previous call) / secondsSinceLast, shown once a client has been
    // seen twice (blank before, or when secondsSinceLast <= 0).
    void setClients(const std::vector<ClientInfo>& clients, double secondsSinceLast);

    QTableWidget* table() const { return table_; }
    QLabel* listeningLabel() const { return listening_; }

private:
    QLabel* listening_;
    QTableWidget* table_;
    std::map<int, std::int64_t> lastCommands_;  // client id -> its command count at the previous call
};

}  // namespace vssim
