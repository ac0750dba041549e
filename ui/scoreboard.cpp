#include "scoreboard.h"

#include <QComboBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>
#include <cmath>

namespace vssim {

namespace {

// The team choosers' entries, in order.
struct ControlChoice {
    TeamControl control;
    const char* text;
    const char* tip;
};
constexpr ControlChoice kControls[] = {
    {TeamControl::Remote, "TCP / by hand",
     "The team's TCP clients send its voltages; any robot can also be driven by keyboard or gamepad "
     "(Drive by hand)."},
    {TeamControl::Builtin, "Built-in", "vssim's sparring team plays this side (docs/game.md)."},
    {TeamControl::Idle, "Idle", "Nobody: the robots get 0 V."},
};

QString teamTitle(Team team) { return team == Team::Yellow ? QObject::tr("yellow") : QObject::tr("blue"); }

}  // namespace

QString gameClockText(double seconds) {
    const int whole = std::isfinite(seconds) && seconds > 0.0 ? static_cast<int>(std::floor(seconds + 1e-9)) : 0;
    return QStringLiteral("%1:%2").arg(whole / 60, 2, 10, QChar('0')).arg(whole % 60, 2, 10, QChar('0'));
}

QString callText(const RefereeCall& call) {
    switch (call.call) {
        case Call::None: return QObject::tr("none");
        case Call::KickOff: return QObject::tr("Kick-off for %1").arg(teamTitle(call.team));
        case Call::FreeBall: return QObject::tr("Free ball, quadrant %1").arg(call.quadrant);
        case Call::PenaltyKick: return QObject::tr("Penalty kick for %1").arg(teamTitle(call.team));
        case Call::GoalKick: return QObject::tr("Goal kick for %1").arg(teamTitle(call.team));
    }
    return {};
}

Scoreboard::Scoreboard(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    score_ = new QLabel(this);
    score_->setObjectName("scoreboard.score");
    QFont big = score_->font();
    big.setPointSizeF(big.pointSizeF() * 1.6);
    big.setBold(true);
    score_->setFont(big);
    score_->setAlignment(Qt::AlignCenter);
    clock_ = new QLabel(this);
    clock_->setObjectName("scoreboard.clock");
    clock_->setAlignment(Qt::AlignCenter);
    clock_->setWordWrap(true);
    phase_ = new QLabel(this);
    phase_->setObjectName("scoreboard.phase");
    phase_->setAlignment(Qt::AlignCenter);
    lastCall_ = new QLabel(this);
    lastCall_->setObjectName("scoreboard.lastCall");
    lastCall_->setWordWrap(true);
    layout->addWidget(score_);
    layout->addWidget(clock_);
    layout->addWidget(phase_);
    layout->addWidget(lastCall_);

    auto* referee = new QGridLayout;
    gameOn_ = new QPushButton(tr("Game on"), this);
    gameOn_->setObjectName("scoreboard.gameOn");
    gameOn_->setToolTip(tr("GAME_ON now, without waiting for the end of the stop."));
    halt_ = new QPushButton(tr("Halt"), this);
    halt_->setObjectName("scoreboard.halt");
    halt_->setToolTip(tr("HALT: every robot at 0 V and the clock stopped until Game on."));
    referee->addWidget(gameOn_, 0, 0, 1, 2);
    referee->addWidget(halt_, 0, 2, 1, 2);
    connect(gameOn_, &QPushButton::clicked, this, &Scoreboard::gameOnRequested);
    connect(halt_, &QPushButton::clicked, this, &Scoreboard::haltRequested);

    callTeam_ = new QComboBox(this);
    callTeam_->setObjectName("scoreboard.callTeam");
    callTeam_->addItem(tr("for yellow"), int(Team::Yellow));
    callTeam_->addItem(tr("for blue"), int(Team::Blue));
    callTeam_->setToolTip(tr("The team a kick-off, penalty kick or goal kick is called for."));
    auto addCall = [this, referee](const QString& text, const char* name, Call call, int quadrant, int row, int col,
                                   int span) {
        auto* b = new QPushButton(text, this);
        b->setObjectName(name);
        referee->addWidget(b, row, col, 1, span);
        callButtons_.append(b);
        connect(b, &QPushButton::clicked, this,
                [this, call, quadrant] { emit callRequested(call, Team(callTeam_->currentData().toInt()), quadrant); });
    };
    referee->addWidget(callTeam_, 1, 0, 1, 4);
    addCall(tr("Kick-off"), "scoreboard.kickOff", Call::KickOff, 0, 2, 0, 2);
    addCall(tr("Penalty"), "scoreboard.penalty", Call::PenaltyKick, 0, 2, 2, 2);
    addCall(tr("Goal kick"), "scoreboard.goalKick", Call::GoalKick, 0, 3, 0, 4);
    referee->addWidget(new QLabel(tr("Free ball in"), this), 4, 0, 1, 4);
    for (int q = 1; q <= 4; ++q) {
        addCall(tr("Q%1").arg(q), QByteArray("scoreboard.freeBall") + QByteArray::number(q), Call::FreeBall, q, 5,
                q - 1, 1);
        callButtons_.back()->setToolTip(tr("Free ball in quadrant %1 (counter-clockwise from x > 0, y > 0)").arg(q));
    }
    layout->addLayout(referee);

    auto* teams = new QFormLayout;
    teams->setRowWrapPolicy(QFormLayout::WrapAllRows);
    auto chooser = [this](Team team, const char* name) {
        auto* box = new QComboBox(this);
        box->setObjectName(name);
        for (const ControlChoice& c : kControls) {
            box->addItem(tr(c.text), int(c.control));
            box->setItemData(box->count() - 1, tr(c.tip), Qt::ToolTipRole);
        }
        connect(box, &QComboBox::currentIndexChanged, this, [this, box, team](int) {
            if (!updating_) emit teamControlRequested(team, TeamControl(box->currentData().toInt()));
        });
        return box;
    };
    yellowControl_ = chooser(Team::Yellow, "scoreboard.yellowControl");
    blueControl_ = chooser(Team::Blue, "scoreboard.blueControl");
    teams->addRow(tr("Yellow played by"), yellowControl_);
    teams->addRow(tr("Blue played by"), blueControl_);
    layout->addLayout(teams);
    layout->addStretch(1);
    setGame(GameState{}, GameRules{}, TeamControl::Remote, TeamControl::Remote);
}

void Scoreboard::setGame(const GameState& game, const GameRules& rules, TeamControl yellow, TeamControl blue) {
    const bool referee = rules.referee;
    score_->setText(tr("Yellow %1 : %2 Blue").arg(game.goals[0]).arg(game.goals[1]));
    if (referee)
        clock_->setText(tr("Half %1 of %2 · %3 of %4")
                            .arg(game.half)
                            .arg(rules.halves)
                            .arg(gameClockText(game.clock), gameClockText(rules.half_duration)));
    else
        clock_->setText(tr("Referee off: no clock, no score, no fouls"));
    switch (game.phase) {
        case GamePhase::GameOn: phase_->setText(referee ? tr("GAME ON") : QString()); break;
        case GamePhase::Stop: phase_->setText(tr("STOP (game on in %1 s)").arg(game.stopLeft, 0, 'f', 1)); break;
        case GamePhase::Halt: phase_->setText(tr("HALT")); break;
        case GamePhase::Finished: phase_->setText(tr("FULL TIME")); break;
    }
    if (referee && game.last.call != Call::None)
        lastCall_->setText(tr("Last call: %1: %2 (half %3, %4)")
                               .arg(callText(game.last), QString::fromStdString(game.last.reason))
                               .arg(game.last.half)
                               .arg(gameClockText(game.last.clock)));
    else
        lastCall_->setText(referee ? tr("No call yet") : QString());
    const bool live = referee && game.phase != GamePhase::Finished;
    gameOn_->setEnabled(live && game.phase != GamePhase::GameOn);
    halt_->setEnabled(live && game.phase != GamePhase::Halt);
    callTeam_->setEnabled(live);
    for (QPushButton* b : callButtons_) b->setEnabled(live);
    updating_ = true;
    yellowControl_->setCurrentIndex(yellowControl_->findData(int(yellow)));
    blueControl_->setCurrentIndex(blueControl_->findData(int(blue)));
    updating_ = false;
}

QString Scoreboard::scoreText() const { return score_->text(); }
QString Scoreboard::clockText() const { return clock_->text(); }
QString Scoreboard::phaseText() const { return phase_->text(); }
QString Scoreboard::lastCallText() const { return lastCall_->text(); }

}  // namespace vssim
