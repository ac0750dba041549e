// The TCP clients of the control server, one table row each, under a
// "Listening on ADDRESS:PORT" line. Fed by the main window from
// ControlServer::clients(); never talks to the server.
#pragma once

#include <QWidget>
#include <map>
#include <vector>

#include "firasim/firasim_server.h"
#include "net/control_server.h"

class QCheckBox;
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

    // FIRASim's interface: its switch, and one status line (ports, packets, errors).
    void showFirasim(const FirasimServer& server);
    void showFirasimOff(const QString& why = {});  // unchecked; `why` it is off (e.g. the port is taken)

    QTableWidget* table() const { return table_; }
    QCheckBox* firasimBox() const { return firasim_; }
    QLabel* firasimLabel() const { return firasimStatus_; }
    QLabel* listeningLabel() const { return listening_; }

signals:
    // The person switched FIRASim's interface on or off.
    void firasimToggled(bool on);

private:
    QLabel* listening_;
    QTableWidget* table_;
    QCheckBox* firasim_;
    QLabel* firasimStatus_;
    std::map<int, std::int64_t> lastCommands_;  // client id -> its command count at the previous call
};

}  // namespace vssim
