/*
 * holo peer harness: a probe compiled into Java 3D 1.5.2's own package
 * com.sun.j3d.utils.geometry.compression, so that it can reach the
 * package-private decoder (GeometryDecompressor), the generalized-strip
 * converter (GeneralizedStrip) and the package fields of CompressionStream.
 *
 * Written for the holo project. It calls the Java 3D classes; it copies none
 * of their code. Nothing here creates a javax.media.j3d scene-graph object
 * (Shape3D, GeometryArray, ...), so the decode path never needs a display.
 */
package com.sun.j3d.utils.geometry.compression;

import java.lang.reflect.Field;
import java.util.ArrayList;
import java.util.List;
import javax.vecmath.Color4f;
import javax.vecmath.Point3f;
import javax.vecmath.Vector3f;

public final class CgProbe extends GeometryDecompressor {

    /** One vertex exactly as the decoder hands it to its back end (outputVertex). */
    public static final class Vertex {
        /** 2-bit replace code: 0 RESTART_CW, 1 RESTART_CCW, 2 REPLACE_MIDDLE, 3 REPLACE_OLDEST. */
        public int flag;
        /** Floats as Java 3D computes them (position v/32768, normal from its table, colour v/32768). */
        public float x, y, z, nx, ny, nz, r, g, b, a;
        /** The decoder's integer state when it output this vertex (only with quantized capture). */
        public int qx, qy, qz, sextant, octant, u, v, qr, qg, qb, qa;
    }

    /** A run of vertices with one vertex format (the Shape3D back end makes one shape per run). */
    public static final class Segment implements GeneralizedStripFlags {
        public final boolean normals, colors, alpha;
        public final List<Vertex> vertices = new ArrayList<Vertex>();
        /** Triangles as indices into vertices, from GeneralizedStrip.toTriangles(this, FRONTFACE_CCW). */
        public int[] triangles = new int[0];

        public Segment(boolean normals, boolean colors, boolean alpha) {
            this.normals = normals;
            this.colors = colors;
            this.alpha = alpha;
        }

        public int getFlagCount() {
            return vertices.size();
        }

        public int getFlag(int i) {
            return vertices.get(i).flag;
        }
    }

    /** Decoded content of one compressed-geometry object. */
    public static final class Result {
        public final List<Segment> segments = new ArrayList<Segment>();
        public int vertexCount;
        public int triangleCount;
    }

    private static Field fX, fY, fZ, fR, fG, fB, fA, fSex, fOct, fU, fV;

    private static Field field(String name) throws ReflectiveOperationException {
        Field f = GeometryDecompressor.class.getDeclaredField(name);
        f.setAccessible(true);
        return f;
    }

    private final boolean quantized;
    private final boolean triangulate;
    private Result result;
    private Segment current;

    /**
     * @param quantized  also record the decoder's integer state per vertex (reflection on its
     *                   private fields curX.., curSex..; slower)
     * @param triangulate run GeneralizedStrip.toTriangles on every segment
     */
    public CgProbe(boolean quantized, boolean triangulate) {
        this.quantized = quantized;
        this.triangulate = triangulate;
        if (quantized && fX == null) {
            try {
                fX = field("curX"); fY = field("curY"); fZ = field("curZ");
                fR = field("curR"); fG = field("curG"); fB = field("curB"); fA = field("curA");
                fSex = field("curSex"); fOct = field("curOct"); fU = field("curU"); fV = field("curV");
            } catch (ReflectiveOperationException e) {
                throw new IllegalStateException("cannot read GeometryDecompressor state", e);
            }
        }
    }

    /**
     * Decode one object. A fresh CgProbe per object behaves like Java 3D's own
     * CompressedGeometryData.decompress(), which makes a new decompressor each time.
     * Reusing one CgProbe keeps the decoder state (tables, mesh buffer, current values)
     * across calls, as GeometryDecompressor does.
     */
    public Result decode(CompressedGeometryData cg) {
        CompressedGeometryData.Header h = new CompressedGeometryData.Header();
        cg.getCompressedGeometryHeader(h);
        byte[] data;
        int start;
        if (cg.isByReference()) {
            data = cg.getCompressedGeometryRef();
            start = h.start;
        } else {
            data = new byte[h.size];
            cg.getCompressedGeometry(data);
            start = 0;
        }
        return decode(h, data, start);
    }

    /** Decode h.size bytes of data from start. */
    public Result decode(CompressedGeometryData.Header h, byte[] data, int start) {
        if (!checkVersion(h.majorVersionNumber, h.minorVersionNumber)) {
            throw new IllegalArgumentException("compressed geometry version "
                    + h.majorVersionNumber + "." + h.minorVersionNumber + " not supported");
        }
        result = new Result();
        current = null;
        decompress(start, h.size, data);
        finish();
        Result r = result;
        result = null;
        current = null;
        return r;
    }

    private void finish() {
        if (current == null) {
            return;
        }
        if (triangulate && current.vertices.size() > 0) {
            int[] t = GeneralizedStrip.toTriangles(current, GeneralizedStripFlags.FRONTFACE_CCW);
            current.triangles = t == null ? new int[0] : t;
        }
        result.vertexCount += current.vertices.size();
        result.triangleCount += current.triangles.length / 3;
        result.segments.add(current);
        current = null;
    }

    // --- GeometryDecompressor back end -------------------------------------

    void outputVertexFormat(boolean bundlingNorm, boolean bundlingColor, boolean doingAlpha) {
        finish();
        current = new Segment(bundlingNorm, bundlingColor, bundlingColor && doingAlpha);
    }

    void outputVertex(Point3f p, Vector3f n, Color4f c, int flag) {
        if (current == null) {
            // A vertex before any setState: Java 3D's Shape3D back end would throw
            // (its vertex list is null); record it in a format-less segment instead.
            current = new Segment(false, false, false);
        }
        Vertex v = new Vertex();
        v.flag = flag;
        v.x = p.x; v.y = p.y; v.z = p.z;
        v.nx = n.x; v.ny = n.y; v.nz = n.z;
        v.r = c.x; v.g = c.y; v.b = c.z; v.a = c.w;
        if (quantized) {
            try {
                v.qx = fX.getShort(this); v.qy = fY.getShort(this); v.qz = fZ.getShort(this);
                v.qr = fR.getShort(this); v.qg = fG.getShort(this);
                v.qb = fB.getShort(this); v.qa = fA.getShort(this);
                v.sextant = fSex.getInt(this); v.octant = fOct.getInt(this);
                v.u = fU.getInt(this); v.v = fV.getInt(this);
            } catch (IllegalAccessException e) {
                throw new IllegalStateException(e);
            }
        }
        current.vertices.add(v);
    }

    // A global colour or normal change (not bundled): like the Shape3D back end,
    // start a new run when vertices are pending; the floats recorded per vertex are
    // the decoder's current values either way.
    void outputColor(Color4f color) {
        if (current != null && current.vertices.size() > 0) {
            Segment s = current;
            finish();
            current = new Segment(s.normals, s.colors, s.alpha);
        }
    }

    void outputNormal(Vector3f normal) {
        if (current != null && !current.normals && current.vertices.size() > 0) {
            Segment s = current;
            finish();
            current = new Segment(s.normals, s.colors, s.alpha);
        }
    }

    // --- encoder side: the package fields the public API does not show -------

    /** {center x, y, z, scale}: model = normalised / scale + center. */
    public static double[] centerAndScale(CompressionStream s) {
        return new double[] {s.center[0], s.center[1], s.center[2], s.scale};
    }

    /** {vertexCount, meshReferenceCount, byteCount} as counted by the stream. */
    public static int[] streamCounts(CompressionStream s) {
        return new int[] {s.getVertexCount(), s.getMeshReferenceCount(), s.getByteCount()};
    }

    /** {vertexColors, vertexColor3, vertexColor4, vertexNormals} as CompressionStream saw the input. */
    public static boolean[] streamFormat(CompressionStream s) {
        return new boolean[] {s.vertexColors, s.vertexColor3, s.vertexColor4, s.vertexNormals};
    }
}
