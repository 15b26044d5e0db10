// Decodes every event of an LCM log the way lcm-spy's subscriber does
// (lcm.spy.Spy.MySubscriber in LCM 1.3.1: read the fingerprint, reset, look the
// class up in lcm.spy.LCMTypeDatabase, construct it from the DataInput), and
// checks that exactly the authentication trailer is left over.
// Usage: java -cp lcm.jar:dynapath_lcmtypes.jar:DIR SpyDecode LOG TRAILER_BYTES
// Prints "decoded N of M events: TYPE=COUNT ..." and exits 1 if any failed.

import java.io.DataInput;
import java.util.TreeMap;

public class SpyDecode {
  public static void main(String[] args) throws Exception {
    lcm.logging.Log log = new lcm.logging.Log(args[0], "r");
    int trailer = Integer.parseInt(args[1]);
    lcm.spy.LCMTypeDatabase types = new lcm.spy.LCMTypeDatabase();
    TreeMap<String, Integer> counts = new TreeMap<>();
    int events = 0, decoded = 0;
    while (true) {
      lcm.logging.Log.Event event;
      try {
        event = log.readNext();
      } catch (java.io.EOFException end) {
        break;
      }
      ++events;
      lcm.lcm.LCMDataInputStream dins = new lcm.lcm.LCMDataInputStream(event.data);
      long fingerprint = dins.available() >= 8 ? dins.readLong() : -1;
      dins.reset();
      Class<?> cls = types.getClassByFingerprint(fingerprint);
      if (cls == null) {
        System.out.println("no type for an event on " + event.channel);
        continue;
      }
      try {
        cls.getConstructor(DataInput.class).newInstance(dins);
      } catch (Exception e) {
        System.out.println("cannot decode " + cls.getName() + " on " + event.channel + ": " + e);
        continue;
      }
      if (dins.available() != trailer) {
        System.out.println(cls.getName() + " on " + event.channel + " left " + dins.available()
            + " bytes, expected the " + trailer + "-byte trailer");
        continue;
      }
      ++decoded;
      counts.merge(cls.getSimpleName(), 1, Integer::sum);
    }
    System.out.println("decoded " + decoded + " of " + events + " events: " + counts);
    System.exit(decoded == events && events > 0 ? 0 : 1);
  }
}
