// The game at a glance and at hand (docs/app.md, "The game"): the score, the
// half and its clock, the referee's state and last call; buttons to put the
// game on, halt it and call a foul (kick-off, free ball per quadrant,
// penalty, goal kick); and who plays each team (TCP clients or a person at
// the keyboard or gamepad, the built-in team, nobody). Fed by the main
// window from the snapshots; its buttons only emit requests.
#pragma once

#include <QWidget>

#include "vssim/game/game_state.h"

class QComboBox;
class QLabel;
class QPushButton;

namespace vssim {

class Scoreboard : public QWidget {
    Q_OBJECT
public:
    explicit Scoreboard(QWidget* parent = nullptr);

    // Shows a game; with the referee off, only the team choosers work.
    void setGame(const GameState& game, const GameRules& rules, TeamControl yellow, TeamControl blue);

    // "Yellow 2 : 1 Blue", "Half 1 · 02:13 of 05:00", "STOP (3.2 s)", and
    // "Free ball, quadrant 2: ball stuck (half 1, 01:12)" (for tests and the status line).
    QString scoreText() const;
    QString clockText() const;
    QString phaseText() const;
    QString lastCallText() const;

signals:
    void gameOnRequested();
    void haltRequested();
    void callRequested(vssim::Call call, vssim::Team team, int quadrant);
    void teamControlRequested(vssim::Team team, vssim::TeamControl control);

private:
    QLabel* score_;
    QLabel* clock_;
    QLabel* phase_;
    QLabel* lastCall_;
    QPushButton* gameOn_;
    QPushButton* halt_;
    QComboBox* callTeam_;  // the team a kick-off, penalty or goal kick is for
    QList<QPushButton*> callButtons_;
    QComboBox* yellowControl_;
    QComboBox* blueControl_;
    bool updating_ = false;  // setGame() is moving the choosers: no requests
};

// "02:13": minutes and seconds of game time, rounded down.
QString gameClockText(double seconds);
// "Free ball, quadrant 2", "Penalty kick for blue", ...
QString callText(const RefereeCall& call);

}  // namespace vssim
