def sub(p, old, new, count=1):
    s=open(p).read()
    assert old in s, (p, old[:70])
    s=s.replace(old,new,count)
    open(p,'w').write(s)
R='/work/wt-machine/'
sub(R+'src/interp/codes.cpp', """    Code{'G',  860, G::Motion,      S::Motion,      run_cycle,        "RLP"},
""", """    Code{'G',  860, G::Motion,      S::Motion,      run_cycle,        "RLP"},
    Code{'G',  870, G::Motion,      S::Motion,      run_cycle,        "RLIJK"},
    Code{'G',  880, G::Motion,      S::Motion,      run_cycle,        "RLP"},
""")
sub(R+'src/interp/interpreter.hpp', """  double cycle_r = 0.0, cycle_bottom = 0.0, cycle_p = 0.0, cycle_q = 0.0;  ///< sticky R Z P Q
""", """  double cycle_r = 0.0, cycle_bottom = 0.0, cycle_p = 0.0, cycle_q = 0.0;  ///< sticky R Z P Q
  std::array<double, 3> cycle_ijk{};  ///< G87's sticky I J K (the back-bore offsets)
""")
p=R+'src/interp/steps_cycles.cpp'
sub(p, """  const bool needs_p = g == 820 || g == 860 || g == 890;""", """  const bool needs_p = g == 820 || g == 860 || g == 880 || g == 890;""")
sub(p, """  if ((g == 740 || g == 840 || g == 860) && s.spindle_dir == 0)""", """  if (entering && g == 870)  // G87: I, J and K on the first block (LinuxCNC)
    for (const char l : {'I', 'J', 'K'})
      if (!w.has(l))
        return ctx.fail(ErrorCode::MissingWord, loc,
                        fmt::format("G87 without {} (the back-bore offsets I J and level K)", l));
  if ((g == 740 || g == 840 || g == 860 || g == 870 || g == 880) && s.spindle_dir == 0)""")
sub(p, """  const double q = w.has('Q') ? w['Q']->value : s.cycle_q;
""", """  const double q = w.has('Q') ? w['Q']->value : s.cycle_q;
  std::array<double, 3> ijk = s.cycle_ijk;  // G87: I J K by program axis X Y Z
  for (int i = 0; i < 3; ++i)
    if (const auto* iw = w["IJK"[i]]) ijk[static_cast<std::size_t>(i)] = iw->value;
""")
sub(p, """      case 890:  // feed in, dwell, feed out to clear""", """      case 870: {  // back boring: in beside the hole (the I J K offsets), up through it, out
        const double oa = a + ijk[static_cast<std::size_t>(ax.a)];
        const double ob = b + ijk[static_cast<std::size_t>(ax.b)];
        double middle = ijk[static_cast<std::size_t>(ax.c)];
        if (s.incremental) middle += bottom;  // K is relative to the bottom in G91
        const int dir = s.spindle_dir;
        const int orient = dir > 0 ? 2 : 3;  // LinuxCNC's CANON_CLOCKWISE / _COUNTERCLOCKWISE
        ok = run.traverse(oa, ob, r);
        if (ok) {
          run.spindle(0);
          emit_io(ctx, EventKind::SpindleOrient, orient, 0.0);
        }
        ok = ok && run.traverse(oa, ob, bottom) && run.traverse(a, b, bottom);
        if (ok) emit_io(ctx, EventKind::SpindleStart, dir, s.spindle_rpm);
        ok = ok && run.feed(a, b, middle) && run.feed(a, b, bottom);
        if (ok) {
          run.spindle(0);
          emit_io(ctx, EventKind::SpindleOrient, orient, 0.0);
        }
        ok = ok && run.traverse(oa, ob, bottom) && run.traverse(oa, ob, clear) &&
             run.traverse(a, b, clear);
        if (ok) emit_io(ctx, EventKind::SpindleStart, dir, s.spindle_rpm);
        break;
      }
      case 880: {  // feed in, dwell, spindle stop, program stop (the operator retracts by hand)
        ok = run.feed(a, b, bottom);
        if (!ok) break;
        run.dwell(p);
        run.spindle(0);
        Event stop;
        stop.line = ctx.block.line;
        stop.kind = EventKind::Pause;
        stop.index = 0;
        ctx.out.emplace_back(std::in_place_type<Event>, std::move(stop));
        if (ctx.machine.pause_s > 0.0)
          ctx.out.emplace_back(std::in_place_type<Dwell>,
                               Dwell{ctx.block.line, ctx.machine.pause_s, true});
        emit_io(ctx, EventKind::SpindleStart, s.spindle_dir, s.spindle_rpm);
        break;
      }
      case 890:  // feed in, dwell, feed out to clear""")
sub(p, """    if (!ok) return false;
    cc = clear;
  }""", """    if (!ok) return false;
    cc = g == 880 ? bottom : clear;  // G88 stays at the bottom (rs274 does not retract)
  }""")
sub(p, """  if (w.has('Q')) s.cycle_q = q;
  s.cycle_mode = g;""", """  if (w.has('Q')) s.cycle_q = q;
  if (g == 870) s.cycle_ijk = ijk;
  s.cycle_mode = g;""")
