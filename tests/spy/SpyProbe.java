// A Java agent for the lcm-spy test: loaded into the lcm-spy process that deploy/lcm-spy.sh
// starts (JAVA_TOOL_OPTIONS=-javaagent:spy_probe.jar=out=FILE,shot=PNG), it reports what the
// spy's window shows, so the test checks lcm-spy itself rather than a re-implementation.
//
// Every 250 ms it rewrites FILE (atomically) with:
//   tick N                                  the probe is alive; N grows
//   frame <title> visible=<0|1> <w>x<h>     each top-level window
//   column <i> <name>                       the channel table's header
//   row <cell>\t<cell>...                   each row of the channel table as displayed
//                                           (Channel, Type, Num Msgs, Hz, ...); Type is the
//                                           decoded class's name or "?? <fingerprint>"
//   decoded <channel>\tclass=<c>\treceived=<n>\terrors=<n>\t<field>=<value>...
//                                           the message lcm-spy decoded last on the channel (the
//                                           object its viewer shows), read from the spy's data
// When PNG.request exists it captures the spy's main window into PNG and deletes the request.
// If the request names a channel, it first opens that channel's viewer (as a double click on
// its row does), lays both windows out one above the other, and captures both. Apart from
// that it only reads: it never changes the spy's state.

import java.awt.Component;
import java.awt.Container;
import java.awt.Frame;
import java.awt.Rectangle;
import java.awt.Robot;
import java.awt.image.BufferedImage;
import java.io.File;
import java.io.PrintWriter;
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Method;
import java.lang.reflect.Modifier;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.StandardCopyOption;
import java.util.ArrayList;
import java.util.Map;
import javax.imageio.ImageIO;
import javax.swing.JFrame;
import javax.swing.JTable;
import javax.swing.SwingUtilities;
import javax.swing.table.TableModel;

public final class SpyProbe {
  private static File out;
  private static File shot;

  public static void premain(String args) {
    for (String kv : (args == null ? "" : args).split(",")) {
      if (kv.startsWith("out=")) out = new File(kv.substring(4));
      if (kv.startsWith("shot=")) shot = new File(kv.substring(5));
    }
    if (out == null) {
      System.err.println("SpyProbe: no out=FILE given; probe disabled");
      return;
    }
    Thread t = new Thread(SpyProbe::loop, "SpyProbe");
    t.setDaemon(true);
    t.start();
  }

  private static void loop() {
    for (long tick = 0;; ++tick) {
      try {
        Thread.sleep(250);
        final StringBuilder sb = new StringBuilder("tick " + tick + "\n");
        final JFrame[] main = new JFrame[1];
        if (Frame.getFrames().length > 0) {
          SwingUtilities.invokeAndWait(() -> snapshot(sb, main));
        }
        write(sb.toString());
        File request = shot == null ? null : new File(shot.getPath() + ".request");
        if (request != null && request.exists() && main[0] != null) {
          String channel = new String(Files.readAllBytes(request.toPath()),
              StandardCharsets.UTF_8).trim();
          capture(main[0], channel);
          request.delete();
        }
      } catch (InterruptedException e) {
        return;
      } catch (Throwable e) {
        // The spy's lists change under us (LCM thread): try again on the next tick.
        try {
          write("tick " + tick + "\nerror " + e + "\n");
        } catch (Exception ignored) {
        }
      }
    }
  }

  // On the event thread: the windows, the channel table as shown, and the decoded messages.
  private static void snapshot(StringBuilder sb, JFrame[] main) {
    for (Frame f : Frame.getFrames()) {
      if (!f.isDisplayable()) continue;
      sb.append("frame ").append(f.getTitle()).append(" visible=").append(f.isShowing() ? 1 : 0)
          .append(' ').append(f.getWidth()).append('x').append(f.getHeight()).append('\n');
      JTable table = findTable(f);
      if (table == null) continue;
      if (f instanceof JFrame) main[0] = (JFrame) f;
      for (int c = 0; c < table.getColumnCount(); ++c) {
        sb.append("column ").append(c).append(' ').append(table.getColumnName(c)).append('\n');
      }
      for (int r = 0; r < table.getRowCount(); ++r) {
        sb.append("row");
        for (int c = 0; c < table.getColumnCount(); ++c) {
          Object v = table.getValueAt(r, c);
          sb.append(c == 0 ? ' ' : '\t').append(v == null ? "" : v.toString().trim());
        }
        sb.append('\n');
      }
      decoded(sb, table.getModel());
    }
  }

  // The spy's own per-channel data, reached from the table model: TableSorter.tableModel is the
  // Spy's ChannelTableModel, whose enclosing Spy holds channelMap (name -> ChannelData).
  private static void decoded(StringBuilder sb, TableModel model) {
    try {
      Object inner = field(model, "tableModel");
      Object spy = field(inner, "this$0");
      Map<?, ?> channels = (Map<?, ?>) field(spy, "channelMap");
      for (Object cd : new ArrayList<Object>(channels.values())) {
        Object cls = field(cd, "cls");
        Object last = field(cd, "last");
        sb.append("decoded ").append(field(cd, "name"))
            .append("\tclass=").append(cls == null ? "none" : ((Class<?>) cls).getName())
            .append("\treceived=").append(field(cd, "nreceived"))
            .append("\terrors=").append(field(cd, "nerrors"));
        if (last != null) fields(sb, last);
        sb.append('\n');
      }
    } catch (ReflectiveOperationException | ClassCastException e) {
      sb.append("decoded-error ").append(e).append('\n');
    }
  }

  // Public instance fields: scalars and strings as name=value, arrays as name[0]=first element.
  private static void fields(StringBuilder sb, Object msg) {
    for (Field f : msg.getClass().getFields()) {
      if (Modifier.isStatic(f.getModifiers())) continue;
      try {
        Object v = f.get(msg);
        if (v != null && v.getClass().isArray()) {
          if (Array.getLength(v) == 0) continue;
          Object first = Array.get(v, 0);
          if (first == null || first.getClass().isArray()) continue;
          sb.append('\t').append(f.getName()).append("[0]=").append(first);
        } else {
          sb.append('\t').append(f.getName()).append('=').append(v);
        }
      } catch (IllegalAccessException ignored) {
      }
    }
  }

  private static Object field(Object o, String name) throws ReflectiveOperationException {
    for (Class<?> c = o.getClass(); c != null; c = c.getSuperclass()) {
      try {
        Field f = c.getDeclaredField(name);
        f.setAccessible(true);
        return f.get(o);
      } catch (NoSuchFieldException e) {
        // look in the superclass
      }
    }
    throw new NoSuchFieldException(o.getClass().getName() + "." + name);
  }

  private static JTable findTable(Component c) {
    if (c instanceof JTable) return (JTable) c;
    if (c instanceof Container) {
      for (Component child : ((Container) c).getComponents()) {
        JTable t = findTable(child);
        if (t != null) return t;
      }
    }
    return null;
  }

  // What is on the screen where the window(s) are (Robot reads the X server's framebuffer).
  private static void capture(JFrame frame, String channel) throws Exception {
    final Rectangle[] r = new Rectangle[1];
    final JFrame[] viewer = new JFrame[1];
    if (!channel.isEmpty()) {
      SwingUtilities.invokeAndWait(() -> {
        try {
          JTable table = findTable(frame);
          Object spy = field(field(table.getModel(), "tableModel"), "this$0");
          Object cd = ((Map<?, ?>) field(spy, "channelMap")).get(channel);
          if (cd == null) return;
          Method open = spy.getClass().getDeclaredMethod("createViewer", cd.getClass());
          open.setAccessible(true);
          open.invoke(spy, cd);
          viewer[0] = (JFrame) field(cd, "viewerFrame");
          frame.setBounds(0, 0, 800, 150);
          viewer[0].setBounds(0, 155, 800, 330);
        } catch (ReflectiveOperationException e) {
          System.err.println("SpyProbe: cannot open a viewer for " + channel + ": " + e);
        }
      });
      Thread.sleep(1500);  // a few messages, so the viewer shows decoded values
    }
    SwingUtilities.invokeAndWait(() -> {
      r[0] = new Rectangle(frame.getLocationOnScreen(), frame.getSize());
      if (viewer[0] != null) {
        r[0] = r[0].union(new Rectangle(viewer[0].getLocationOnScreen(), viewer[0].getSize()));
      }
    });
    BufferedImage img = new Robot().createScreenCapture(r[0]);
    File tmp = new File(shot.getPath() + ".tmp");
    ImageIO.write(img, "png", tmp);
    Files.move(tmp.toPath(), shot.toPath(), StandardCopyOption.REPLACE_EXISTING,
        StandardCopyOption.ATOMIC_MOVE);
  }

  private static void write(String text) throws Exception {
    File tmp = new File(out.getPath() + ".tmp");
    try (PrintWriter w = new PrintWriter(tmp, StandardCharsets.UTF_8.name())) {
      w.print(text);
    }
    Files.move(tmp.toPath(), out.toPath(), StandardCopyOption.REPLACE_EXISTING,
        StandardCopyOption.ATOMIC_MOVE);
  }
}
