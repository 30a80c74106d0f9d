/*
 * holo peer harness for Java 3D 1.5.2 compressed geometry (.cg files).
 * Written for the holo project; see tests/peer/java3d/README.md.
 *
 *   decode [--hex|--quantized] [--stream|--indexed] [--core] FILE.cg
 *   encode IN.ply OUT.cg POSBITS COLORBITS NORMALBITS [--no-stripify] [--rgb] [--no-normals] [--no-colors] [--append]
 *   time FILE.cg N
 */
import com.sun.j3d.utils.geometry.GeometryInfo;
import com.sun.j3d.utils.geometry.Stripifier;
import com.sun.j3d.utils.geometry.compression.CgProbe;
import com.sun.j3d.utils.geometry.compression.CompressedGeometryData;
import com.sun.j3d.utils.geometry.compression.CompressedGeometryFile;
import com.sun.j3d.utils.geometry.compression.CompressionStream;
import com.sun.j3d.utils.geometry.compression.GeometryCompressor;
import java.io.BufferedReader;
import java.io.BufferedWriter;
import java.io.File;
import java.io.FileReader;
import java.io.IOException;
import java.io.OutputStreamWriter;
import java.io.PrintWriter;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Locale;
import javax.vecmath.Color3f;
import javax.vecmath.Color4f;
import javax.vecmath.Point3d;
import javax.vecmath.Point3f;
import javax.vecmath.Vector3f;

public final class CgTool {

    static void usage() {
        System.err.println(String.join("\n",
                "usage: CgTool decode [--hex|--quantized] [--stream|--indexed] [--core] FILE.cg",
                "       CgTool encode IN.ply OUT.cg POSBITS COLORBITS NORMALBITS"
                        + " [--no-stripify] [--rgb] [--no-normals] [--no-colors] [--append]",
                "       CgTool time FILE.cg N"));
        System.exit(2);
    }

    public static void main(String[] args) throws Exception {
        if (args.length < 1) usage();
        Locale.setDefault(Locale.ROOT);
        switch (args[0]) {
            case "decode": decode(Arrays.copyOfRange(args, 1, args.length)); break;
            case "encode": encode(Arrays.copyOfRange(args, 1, args.length)); break;
            case "time": time(Arrays.copyOfRange(args, 1, args.length)); break;
            default: usage();
        }
    }

    // --- reading .cg -------------------------------------------------------------

    static CompressedGeometryData[] readAll(String path) throws IOException {
        CompressedGeometryFile f = new CompressedGeometryFile(path, false);
        try {
            return f.read();
        } finally {
            f.close();
        }
    }

    static String fileLine(String path) throws IOException {
        CompressedGeometryFile f = new CompressedGeometryFile(path, false);
        try {
            return "cg " + new File(path).getName() + " version " + f.getMajorVersionNumber() + "."
                    + f.getMinorVersionNumber() + "." + f.getMinorMinorVersionNumber()
                    + " objects " + f.getObjectCount();
        } finally {
            f.close();
        }
    }

    static String typeName(int bufferType) {
        switch (bufferType) {
            case CompressedGeometryData.Header.POINT_BUFFER: return "point";
            case CompressedGeometryData.Header.LINE_BUFFER: return "line";
            case CompressedGeometryData.Header.TRIANGLE_BUFFER: return "triangle";
            default: return "unknown" + bufferType;
        }
    }

    // --- decode ------------------------------------------------------------------

    static void decode(String[] a) throws IOException {
        String mode = "float";
        String layout = "triangles";
        String path = null;
        boolean core = false;
        for (String s : a) {
            if (s.equals("--core")) core = true;
            else if (s.equals("--hex")) mode = "hex";
            else if (s.equals("--quantized")) mode = "quantized";
            else if (s.equals("--stream")) layout = "stream";
            else if (s.equals("--indexed")) layout = "indexed";
            else if (path == null) path = s;
            else usage();
        }
        if (path == null || (core && mode.equals("quantized"))) usage();
        PrintWriter out = new PrintWriter(new BufferedWriter(new OutputStreamWriter(System.out, "UTF-8"), 1 << 16));
        out.println("# CgTool decode " + mode + " " + layout + " (Java 3D " + j3dVersion() + ")");
        out.println(fileLine(path));
        CompressedGeometryData[] objs = readAll(path);
        for (int i = 0; i < objs.length; i++) {
            CompressedGeometryData.Header h = new CompressedGeometryData.Header();
            objs[i].getCompressedGeometryHeader(h);
            // A fresh decoder per object, as CompressedGeometryData.decompress() does.
            CgProbe.Result r = core ? coreDecode(objs[i])
                    : new CgProbe(mode.equals("quantized"), true).decode(objs[i]);
            int degenerate = 0;
            for (CgProbe.Segment s : r.segments) degenerate += degenerate(s);
            out.println("object " + i + " type " + typeName(h.bufferType)
                    + " normals " + bit(h.bufferDataPresent, 1) + " colors " + bit(h.bufferDataPresent, 2)
                    + " alpha " + bit(h.bufferDataPresent, 4) + " bytes " + h.size
                    + " segments " + r.segments.size() + " vertices " + r.vertexCount
                    + " triangles " + r.triangleCount + " degenerate " + degenerate);
            for (int k = 0; k < r.segments.size(); k++) {
                CgProbe.Segment s = r.segments.get(k);
                out.println("segment " + k + " normals " + (s.normals ? 1 : 0) + " colors "
                        + (s.colors ? 1 : 0) + " alpha " + (s.alpha ? 1 : 0)
                        + " vertices " + s.vertices.size() + " triangles " + s.triangles.length / 3);
                if (layout.equals("stream")) {
                    for (CgProbe.Vertex v : s.vertices) {
                        out.println(v.flag + " " + vertexText(v, mode));
                    }
                } else if (layout.equals("indexed")) {
                    for (CgProbe.Vertex v : s.vertices) {
                        out.println("v " + v.flag + " " + vertexText(v, mode));
                    }
                    for (int t = 0; t + 2 < s.triangles.length; t += 3) {
                        out.println("t " + s.triangles[t] + " " + s.triangles[t + 1] + " " + s.triangles[t + 2]);
                    }
                } else {
                    for (int t = 0; t < s.triangles.length; t++) {
                        out.println(vertexText(s.vertices.get(s.triangles[t]), mode));
                    }
                }
            }
        }
        out.println("end");
        out.flush();
    }

    /** The same decode through Java 3D's core copy of the decoder (javax.media.j3d). */
    static CgProbe.Result coreDecode(CompressedGeometryData cg) {
        CompressedGeometryData.Header h = new CompressedGeometryData.Header();
        cg.getCompressedGeometryHeader(h);
        byte[] data = new byte[h.size];
        cg.getCompressedGeometry(data);
        return javax.media.j3d.CgCoreProbe.decode(h.majorVersionNumber, h.minorVersionNumber, data, 0, h.size);
    }

    static int bit(int flags, int b) {
        return (flags & b) != 0 ? 1 : 0;
    }

    /** Triangles with two equal decoded positions (the stripifier's joins). */
    static int degenerate(CgProbe.Segment s) {
        int n = 0;
        for (int t = 0; t + 2 < s.triangles.length; t += 3) {
            CgProbe.Vertex a = s.vertices.get(s.triangles[t]);
            CgProbe.Vertex b = s.vertices.get(s.triangles[t + 1]);
            CgProbe.Vertex c = s.vertices.get(s.triangles[t + 2]);
            if (samePos(a, b) || samePos(b, c) || samePos(a, c)) n++;
        }
        return n;
    }

    static boolean samePos(CgProbe.Vertex a, CgProbe.Vertex b) {
        return a.x == b.x && a.y == b.y && a.z == b.z;
    }

    static String vertexText(CgProbe.Vertex v, String mode) {
        StringBuilder sb = new StringBuilder(96);
        if (mode.equals("quantized")) {
            sb.append(v.qx).append(' ').append(v.qy).append(' ').append(v.qz).append(' ')
              .append(v.sextant).append(' ').append(v.octant).append(' ')
              .append(v.u).append(' ').append(v.v).append(' ')
              .append(v.qr).append(' ').append(v.qg).append(' ').append(v.qb).append(' ').append(v.qa);
            return sb.toString();
        }
        float[] f = {v.x, v.y, v.z, v.nx, v.ny, v.nz, v.r, v.g, v.b, v.a};
        for (int i = 0; i < f.length; i++) {
            if (i > 0) sb.append(' ');
            if (mode.equals("hex")) {
                sb.append(String.format("%08x", Float.floatToRawIntBits(f[i])));
            } else {
                sb.append(Float.toString(f[i]));
            }
        }
        return sb.toString();
    }

    static String j3dVersion() {
        Package p = CompressionStream.class.getPackage();
        String v = p == null ? null : p.getImplementationVersion();
        return v == null ? "unknown" : v;
    }

    // --- time --------------------------------------------------------------------------

    static void time(String[] a) throws Exception {
        if (a.length != 2) usage();
        int n = Integer.parseInt(a[1]);
        CompressedGeometryData[] objs = readAll(a[0]);
        long bytes = 0;
        for (CompressedGeometryData o : objs) bytes += o.getByteCount();
        // The first pass runs cold (interpreter, class loading): timed on its own. Then
        // count the triangles, warm up the JIT, and time N passes.
        long c0 = System.nanoTime();
        for (CompressedGeometryData o : objs) new CgProbe(false, true).decode(o);
        double cold = (System.nanoTime() - c0) / 1e9;
        int tris = 0, nondegenerate = 0;
        for (CompressedGeometryData o : objs) {
            CgProbe.Result r = new CgProbe(false, true).decode(o);
            tris += r.triangleCount;
            for (CgProbe.Segment s : r.segments) nondegenerate += s.triangles.length / 3 - degenerate(s);
        }
        int warm = Math.max(5, Math.min(n, 200));
        long sink = 0;
        for (int i = 0; i < warm; i++) {
            for (CompressedGeometryData o : objs) sink += new CgProbe(false, true).decode(o).triangleCount;
        }
        long[] perPass = new long[n];
        long t0 = System.nanoTime();
        for (int i = 0; i < n; i++) {
            long s = System.nanoTime();
            for (CompressedGeometryData o : objs) sink += new CgProbe(false, true).decode(o).triangleCount;
            perPass[i] = System.nanoTime() - s;
        }
        long total = System.nanoTime() - t0;
        Arrays.sort(perPass);
        double median = perPass[n / 2] / 1e9;
        double best = perPass[0] / 1e9;
        System.out.println("file " + a[0] + " bytes " + bytes + " triangles " + tris
                + " nondegenerate " + nondegenerate + " passes " + n + " warmup " + warm);
        System.out.printf("decode+triangles mean %.3f us/pass, median %.3f us, best %.3f us%n",
                total / 1e3 / n, median * 1e6, best * 1e6);
        System.out.printf("triangles/s mean %.0f median %.0f best %.0f (all decoded triangles)%n",
                tris * (double) n / (total / 1e9), tris / median, tris / best);
        System.out.printf("nondegenerate triangles/s mean %.0f median %.0f%n",
                nondegenerate * (double) n / (total / 1e9), nondegenerate / median);
        System.out.printf("cold first pass %.3f ms: %.0f triangles/s (%.0f nondegenerate)%n",
                cold * 1e3, tris / cold, nondegenerate / cold);
        if (sink == 42) System.out.println();
    }

    // --- encode --------------------------------------------------------------------------

    static void encode(String[] a) throws Exception {
        if (a.length < 5) usage();
        String in = a[0], out = a[1];
        int pb = Integer.parseInt(a[2]), cb = Integer.parseInt(a[3]), nb = Integer.parseInt(a[4]);
        boolean stripify = true, rgb = false, normals = true, colors = true, append = false;
        for (int i = 5; i < a.length; i++) {
            switch (a[i]) {
                case "--no-stripify": stripify = false; break;
                case "--rgb": rgb = true; break;
                case "--no-normals": normals = false; break;
                case "--no-colors": colors = false; break;
                case "--append": append = true; break;
                default: usage();
            }
        }
        Ply ply = Ply.read(in);
        normals &= ply.hasNormals;
        colors &= ply.hasColors;
        int nt = ply.faces.length / 3;
        // One entry per triangle corner; indexify() merges equal corners.
        Point3f[] p = new Point3f[nt * 3];
        Vector3f[] n = normals ? new Vector3f[nt * 3] : null;
        Color4f[] c4 = colors && !rgb ? new Color4f[nt * 3] : null;
        Color3f[] c3 = colors && rgb ? new Color3f[nt * 3] : null;
        for (int k = 0; k < nt * 3; k++) {
            int v = ply.faces[k];
            float[] d = ply.vertex[v];
            p[k] = new Point3f(d[0], d[1], d[2]);
            if (n != null) n[k] = new Vector3f(d[3], d[4], d[5]);
            if (c4 != null) c4[k] = new Color4f(d[6], d[7], d[8], d[9]);
            if (c3 != null) c3[k] = new Color3f(d[6], d[7], d[8]);
        }
        GeometryInfo gi = new GeometryInfo(GeometryInfo.TRIANGLE_ARRAY);
        gi.setCoordinates(p);
        if (n != null) gi.setNormals(n);
        if (c4 != null) gi.setColors(c4);
        if (c3 != null) gi.setColors(c3);
        gi.indexify();
        if (stripify) new Stripifier().stripify(gi);

        long t0 = System.nanoTime();
        CompressionStream stream = new CompressionStream(pb, cb, nb, new GeometryInfo[] {gi});
        if (!append) new File(out).delete();
        CompressedGeometryFile file = new CompressedGeometryFile(out, true);
        new GeometryCompressor().compress(stream, file);
        file.close();
        long t1 = System.nanoTime();

        CompressedGeometryData[] objs = readAll(out);
        CompressedGeometryData.Header h = new CompressedGeometryData.Header();
        objs[objs.length - 1].getCompressedGeometryHeader(h);
        Point3d[] mb = stream.getModelBounds();
        Point3d[] nbnd = stream.getNormalizedBounds();
        double[] cs = CgProbe.centerAndScale(stream);
        int[] counts = CgProbe.streamCounts(stream);
        boolean[] fmt = CgProbe.streamFormat(stream);
        System.out.println("input " + new File(in).getName() + " vertices " + ply.vertex.length + " triangles " + nt
                + " normals " + (normals ? 1 : 0) + " colors " + (colors ? (rgb ? "rgb" : "rgba") : "none"));
        System.out.println("options pos " + pb + " color " + cb + " normal " + nb + " stripify " + (stripify ? 1 : 0));
        System.out.println("stream vertices " + counts[0] + " meshrefs " + counts[1]
                + " colors " + (fmt[0] ? 1 : 0) + " color3 " + (fmt[1] ? 1 : 0) + " color4 " + (fmt[2] ? 1 : 0)
                + " normals " + (fmt[3] ? 1 : 0));
        System.out.println("model_bounds " + pt(mb[0]) + " " + pt(mb[1]));
        System.out.println("normalized_bounds " + pt(nbnd[0]) + " " + pt(nbnd[1]));
        System.out.println("center " + cs[0] + " " + cs[1] + " " + cs[2] + " scale " + cs[3]);
        System.out.println("output " + new File(out).getName() + " objects " + objs.length + " stream_bytes " + h.size
                + " file_bytes " + new File(out).length() + " data_present " + h.bufferDataPresent);
        System.out.printf("bytes_per_triangle %.4f (stream bytes / input triangles)%n", h.size / (double) nt);
        // Timing on stderr, so that stdout is the same on every run (it is a fixture).
        System.err.printf("encode_ms %.1f%n", (t1 - t0) / 1e6);
    }

    static String pt(Point3d p) {
        return p.x + " " + p.y + " " + p.z;
    }

    /** ASCII PLY: vertex x y z [nx ny nz] [red green blue [alpha]] (float or uchar), faces as lists. */
    static final class Ply {
        float[][] vertex; // x y z nx ny nz r g b a (colours in [0, 1])
        int[] faces;      // triangle corners (polygons fanned)
        boolean hasNormals, hasColors;

        static Ply read(String path) throws IOException {
            BufferedReader r = new BufferedReader(new FileReader(path));
            try {
                String line = r.readLine();
                if (line == null || !line.trim().equals("ply")) throw new IOException(path + ": not a PLY file");
                int nv = 0, nf = 0;
                String element = null;
                List<String> props = new ArrayList<String>();
                List<Boolean> byteProps = new ArrayList<Boolean>();
                while ((line = r.readLine()) != null) {
                    String[] w = line.trim().split("\\s+");
                    if (w[0].equals("format") && !w[1].equals("ascii")) throw new IOException(path + ": only ASCII PLY");
                    if (w[0].equals("element")) {
                        element = w[1];
                        if (element.equals("vertex")) nv = Integer.parseInt(w[2]);
                        else if (element.equals("face")) nf = Integer.parseInt(w[2]);
                    } else if (w[0].equals("property") && "vertex".equals(element)) {
                        props.add(w[w.length - 1]);
                        byteProps.add(w[1].equals("uchar") || w[1].equals("uint8"));
                    } else if (w[0].equals("end_header")) {
                        break;
                    }
                }
                String[] names = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha"};
                int[] col = new int[names.length];
                for (int i = 0; i < names.length; i++) col[i] = props.indexOf(names[i]);
                if (col[0] < 0 || col[1] < 0 || col[2] < 0) throw new IOException(path + ": no x y z");
                Ply ply = new Ply();
                ply.hasNormals = col[3] >= 0 && col[4] >= 0 && col[5] >= 0;
                ply.hasColors = col[6] >= 0 && col[7] >= 0 && col[8] >= 0;
                ply.vertex = new float[nv][10];
                for (int i = 0; i < nv; i++) {
                    String[] w = r.readLine().trim().split("\\s+");
                    float[] d = ply.vertex[i];
                    d[9] = 1.0f;
                    for (int k = 0; k < names.length; k++) {
                        if (col[k] < 0) continue;
                        float f = Float.parseFloat(w[col[k]]);
                        d[k] = byteProps.get(col[k]) ? f / 255.0f : f;
                    }
                }
                List<Integer> tri = new ArrayList<Integer>();
                for (int i = 0; i < nf; i++) {
                    String[] w = r.readLine().trim().split("\\s+");
                    int count = Integer.parseInt(w[0]);
                    for (int k = 1; k + 1 < count; k++) {
                        tri.add(Integer.parseInt(w[1]));
                        tri.add(Integer.parseInt(w[1 + k]));
                        tri.add(Integer.parseInt(w[2 + k]));
                    }
                }
                ply.faces = new int[tri.size()];
                for (int i = 0; i < ply.faces.length; i++) ply.faces[i] = tri.get(i);
                return ply;
            } finally {
                r.close();
            }
        }
    }
}
