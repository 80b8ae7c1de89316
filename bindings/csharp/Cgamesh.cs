// cgamesh for C# (Unity, Godot, .NET, Mono): P/Invoke declarations of the C ABI
// (include/cgamesh/cgamesh.h) and a thin idiomatic layer over them. One file: copy it next to
// libcgamesh_c (.so, .dylib or .dll) into a project.
//
// - Handles are SafeHandles: a model, pose, live model or change is freed when disposed or
//   collected.
// - A status other than OK becomes an exception of the same hierarchy as Python's:
//   CgameshException > InvalidInputException > FileException; WriteException,
//   TopologyException, SolverException, PlatformException.
// - The per-frame calls (Pose.Sample, Model.Skin, LiveModel.Skin, LiveModel.StepTissue) take
//   arrays the caller keeps and allocate nothing managed: blittable arrays are pinned by the
//   marshaller, not copied.
using System;
using System.Runtime.InteropServices;

namespace Cgamesh
{
    public enum Status
    {
        Ok = 0,
        InvalidArgument = 1,
        File = 2,
        Write = 3,
        Topology = 4,
        Solver = 5,
        Platform = 6,
        OutOfMemory = 7,
        Internal = 8,
    }

    /// <summary>How keys are blended between key times.</summary>
    public enum Blend { Format = 0, Linear = 1, Log = 2 }

    /// <summary>The skinning of eq. (17): cga (exact for any rig), versor, matrix, dqs.</summary>
    public enum Skinning { Cga = 0, Versor = 1, Matrix = 2, Dqs = 3 }

    /// <summary>What an operation changed in one mesh (see cgamesh.h).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct MeshChange
    {
        public int Mesh;
        public int FirstNewVertex;
        public int NewVertices;
        public int NewFaces;
        public int MovedFaces;
        public int RemovedFaces;
    }

    /// <summary>Living tissue's options, with the units of soft/tissue_options.hpp.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct TissueOptions
    {
        public double Density;
        public double AttachmentCompliance;
        public double StretchCompliance;
        public double BendCompliance;
        public double Pretension;
        public double Damping;
        public double Substep;
        public double GravityX, GravityY, GravityZ;
        public double RegionRadius;
        public double ReleaseMargin;
        public int MaxParticles;

        /// <summary>The library's defaults.</summary>
        public static TissueOptions Default
        {
            get
            {
                TissueOptions o;
                Error.Check(Native.cgamesh_tissue_options_default(out o));
                return o;
            }
        }
    }

    public class CgameshException : Exception
    {
        public Status Status { get; private set; }
        public CgameshException(Status status, string message) : base(message) { Status = status; }
    }
    /// <summary>An argument is unusable: a null handle, a wrong buffer size, NaN, a bad name.</summary>
    public class InvalidInputException : CgameshException
    {
        public InvalidInputException(Status status, string message) : base(status, message) { }
    }
    /// <summary>An input file is missing, unreadable or no valid model.</summary>
    public class FileException : InvalidInputException
    {
        public FileException(string message) : base(Status.File, message) { }
    }
    /// <summary>An output file could not be written (nothing was left behind).</summary>
    public class WriteException : CgameshException
    {
        public WriteException(string message) : base(Status.Write, message) { }
    }
    /// <summary>The mesh does not allow the operation (the tool misses it, an open section).</summary>
    public class TopologyException : CgameshException
    {
        public TopologyException(string message) : base(Status.Topology, message) { }
    }
    /// <summary>A numerical method failed (a singular system, a diverging tissue).</summary>
    public class SolverException : CgameshException
    {
        public SolverException(string message) : base(Status.Solver, message) { }
    }
    /// <summary>The machine cannot do what was asked.</summary>
    public class PlatformException : CgameshException
    {
        public PlatformException(string message) : base(Status.Platform, message) { }
    }

    internal static class Error
    {
        internal static void Check(Status status)
        {
            if (status == Status.Ok) return;
            string message = Native.Text(Native.cgamesh_last_error());
            switch (status)
            {
                case Status.InvalidArgument: throw new InvalidInputException(status, message);
                case Status.File: throw new FileException(message);
                case Status.Write: throw new WriteException(message);
                case Status.Topology: throw new TopologyException(message);
                case Status.Solver: throw new SolverException(message);
                case Status.Platform: throw new PlatformException(message);
                case Status.OutOfMemory: throw new OutOfMemoryException(message);
                default: throw new CgameshException(status, message);
            }
        }
    }

    /// <summary>The C functions, one for one (cgamesh.h documents each).</summary>
    public static class Native
    {
        public const string Library = "cgamesh_c";
        public const int AbiVersion = 1;

        internal static string Text(IntPtr utf8)
        {
            return utf8 == IntPtr.Zero ? "" : Marshal.PtrToStringAnsi(utf8);
        }

        /// <summary>A string the library made, freed.</summary>
        internal static string Take(IntPtr utf8)
        {
            try { return Text(utf8); } finally { cgamesh_string_free(utf8); }
        }

        [DllImport(Library)] public static extern IntPtr cgamesh_last_error();
        [DllImport(Library)] public static extern IntPtr cgamesh_status_name(Status status);
        [DllImport(Library)] public static extern IntPtr cgamesh_version();
        [DllImport(Library)] public static extern int cgamesh_abi_version();
        [DllImport(Library)] public static extern void cgamesh_string_free(IntPtr text);

        [DllImport(Library)] public static extern Status cgamesh_model_load(string path, out ModelHandle model);
        [DllImport(Library)] public static extern void cgamesh_model_free(IntPtr model);
        [DllImport(Library)] public static extern Status cgamesh_model_save(ModelHandle model, string path, PoseHandle pose);
        [DllImport(Library)] public static extern Status cgamesh_model_warning_count(ModelHandle model, out UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_model_warning(ModelHandle model, UIntPtr index, out IntPtr text);
        [DllImport(Library)] public static extern Status cgamesh_model_info_json(ModelHandle model, out IntPtr json);
        [DllImport(Library)] public static extern Status cgamesh_model_counts_get(ModelHandle model, out ModelCounts counts);
        [DllImport(Library)] public static extern Status cgamesh_model_mesh_size(ModelHandle model, int mesh, out int vertices, out int faces);
        [DllImport(Library)] public static extern Status cgamesh_model_mesh_positions(ModelHandle model, int mesh, [Out] float[] positions, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_model_mesh_faces(ModelHandle model, int mesh, [Out] int[] faces, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_model_mesh_uvs(ModelHandle model, int mesh, [Out] float[] uvs, UIntPtr count, out int hasUvs);
        [DllImport(Library)] public static extern Status cgamesh_model_joint_index(ModelHandle model, string name, out int joint);
        [DllImport(Library)] public static extern Status cgamesh_model_clip_index(ModelHandle model, string name, out int clip);
        [DllImport(Library)] public static extern Status cgamesh_model_clip_duration(ModelHandle model, int clip, out double seconds);

        [DllImport(Library)] public static extern Status cgamesh_pose_create(ModelHandle model, out PoseHandle pose);
        [DllImport(Library)] public static extern void cgamesh_pose_free(IntPtr pose);
        [DllImport(Library)] public static extern Status cgamesh_pose_sample(PoseHandle pose, ModelHandle model, int clip, double time, Blend blend);
        [DllImport(Library)] public static extern Status cgamesh_pose_rotate(PoseHandle pose, ModelHandle model, int joint, [In] double[] axis, double degrees);
        [DllImport(Library)] public static extern Status cgamesh_pose_translate(PoseHandle pose, ModelHandle model, int joint, [In] double[] translation);
        [DllImport(Library)] public static extern Status cgamesh_pose_scale(PoseHandle pose, ModelHandle model, int joint, double scale);
        [DllImport(Library)] public static extern Status cgamesh_pose_set_morph_weight(PoseHandle pose, ModelHandle model, string target, float weight);
        [DllImport(Library)] public static extern Status cgamesh_pose_clear_edits(PoseHandle pose, ModelHandle model);
        [DllImport(Library)] public static extern Status cgamesh_pose_warning_count(PoseHandle pose, out UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_pose_warning(PoseHandle pose, UIntPtr index, out IntPtr text);

        [DllImport(Library)] public static extern Status cgamesh_model_skin(ModelHandle model, PoseHandle pose, int mesh, Skinning mode,
                                                                             [Out] float[] positions, UIntPtr positionCount,
                                                                             [Out] float[] normals, UIntPtr normalCount);

        [DllImport(Library)] public static extern Status cgamesh_live_create(ModelHandle model, PoseHandle pose, out LiveHandle live);
        [DllImport(Library)] public static extern void cgamesh_live_free(IntPtr live);
        [DllImport(Library)] public static extern Status cgamesh_live_model(LiveHandle live, out ModelHandle model);
        [DllImport(Library)] public static extern Status cgamesh_live_mesh_size(LiveHandle live, int mesh, out int vertices, out int faces);
        [DllImport(Library)] public static extern Status cgamesh_live_mesh_faces(LiveHandle live, int mesh, [Out] int[] faces, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_live_mesh_positions(LiveHandle live, int mesh, [Out] float[] positions, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_live_skin(LiveHandle live, PoseHandle pose, int mesh, Skinning mode,
                                                                            [Out] float[] positions, UIntPtr positionCount,
                                                                            [Out] float[] normals, UIntPtr normalCount);
        [DllImport(Library)] public static extern Status cgamesh_live_cut(LiveHandle live, [In] double[] normal, double d, out ChangeHandle change);
        [DllImport(Library)] public static extern Status cgamesh_live_tear(LiveHandle live, [In] double[] blades, UIntPtr count, double open, out ChangeHandle change);
        [DllImport(Library)] public static extern Status cgamesh_live_drill(LiveHandle live, [In] double[] tip, [In] double[] baseCenter, double radius, int wall, out ChangeHandle change);

        [DllImport(Library)] public static extern void cgamesh_change_free(IntPtr change);
        [DllImport(Library)] public static extern Status cgamesh_change_json(ChangeHandle change, out IntPtr json);
        [DllImport(Library)] public static extern Status cgamesh_change_mesh_count(ChangeHandle change, out UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_change_mesh(ChangeHandle change, UIntPtr index, out MeshChange mesh);
        [DllImport(Library)] public static extern Status cgamesh_change_new_faces(ChangeHandle change, UIntPtr index, [Out] int[] faces, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_change_new_face_corners(ChangeHandle change, UIntPtr index, [Out] int[] corners, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_change_moved_faces(ChangeHandle change, UIntPtr index, [Out] int[] moved, UIntPtr count);
        [DllImport(Library)] public static extern Status cgamesh_change_origins(ChangeHandle change, UIntPtr index, [Out] int[] vertices, [Out] float[] weights, UIntPtr count);

        [DllImport(Library)] public static extern Status cgamesh_tissue_options_default(out TissueOptions options);
        [DllImport(Library)] public static extern Status cgamesh_live_set_tissue(LiveHandle live, ref TissueOptions options);
        [DllImport(Library)] public static extern Status cgamesh_live_clear_tissue(LiveHandle live);
        [DllImport(Library)] public static extern Status cgamesh_live_step_tissue(LiveHandle live, PoseHandle pose, double dt);
        [DllImport(Library)] public static extern Status cgamesh_live_bake_tissue(LiveHandle live, PoseHandle pose);

        [DllImport(Library)] public static extern Status cgamesh_model_deform(ModelHandle model, string specJson, out ModelHandle deformed);
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct ModelCounts
    {
        public int Meshes, Joints, Clips;
    }

    public sealed class ModelHandle : SafeHandle
    {
        public ModelHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Native.cgamesh_model_free(handle); return true; }
    }
    public sealed class PoseHandle : SafeHandle
    {
        public PoseHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Native.cgamesh_pose_free(handle); return true; }
        /// <summary>Stands for "no pose" (the bind pose) where a call accepts NULL.</summary>
        internal static readonly PoseHandle Null = new PoseHandle();
    }
    public sealed class LiveHandle : SafeHandle
    {
        public LiveHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Native.cgamesh_live_free(handle); return true; }
    }
    public sealed class ChangeHandle : SafeHandle
    {
        public ChangeHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Native.cgamesh_change_free(handle); return true; }
    }

    /// <summary>A rigged model: meshes, skins, skeleton, clips, materials.</summary>
    public sealed class Model : IDisposable
    {
        internal readonly ModelHandle Handle;
        internal Model(ModelHandle handle) { Handle = handle; }

        /// <summary>Every format the CLI reads (glTF, FBX, Collada, X, SMD, OBJ, PLY, ...).</summary>
        public static Model Load(string path)
        {
            ModelHandle h;
            Error.Check(Native.cgamesh_model_load(path, out h));
            return new Model(h);
        }

        /// <summary>By the extension: .glb/.gltf rigged, .obj/.ply the surface in `pose`
        /// (null: the bind pose). All or nothing.</summary>
        public void Save(string path, Pose pose = null)
        {
            Error.Check(Native.cgamesh_model_save(Handle, path, pose == null ? PoseHandle.Null : pose.Handle));
        }

        public ModelCounts Counts
        {
            get { ModelCounts c; Error.Check(Native.cgamesh_model_counts_get(Handle, out c)); return c; }
        }

        public string[] Warnings
        {
            get
            {
                UIntPtr n;
                Error.Check(Native.cgamesh_model_warning_count(Handle, out n));
                var out_ = new string[(int)n];
                for (int i = 0; i < out_.Length; ++i)
                {
                    IntPtr text;
                    Error.Check(Native.cgamesh_model_warning(Handle, (UIntPtr)i, out text));
                    out_[i] = Native.Text(text);
                }
                return out_;
            }
        }

        /// <summary>`cgamesh info --json`'s document.</summary>
        public string InfoJson()
        {
            IntPtr json;
            Error.Check(Native.cgamesh_model_info_json(Handle, out json));
            return Native.Take(json);
        }

        public int VertexCount(int mesh) { int v, f; Error.Check(Native.cgamesh_model_mesh_size(Handle, mesh, out v, out f)); return v; }
        public int FaceCount(int mesh) { int v, f; Error.Check(Native.cgamesh_model_mesh_size(Handle, mesh, out v, out f)); return f; }

        /// <summary>Rest positions, #V*3.</summary>
        public float[] RestPositions(int mesh)
        {
            var p = new float[3 * VertexCount(mesh)];
            Error.Check(Native.cgamesh_model_mesh_positions(Handle, mesh, p, (UIntPtr)p.Length));
            return p;
        }

        /// <summary>Faces, #F*3 vertex indices.</summary>
        public int[] Faces(int mesh)
        {
            var f = new int[3 * FaceCount(mesh)];
            Error.Check(Native.cgamesh_model_mesh_faces(Handle, mesh, f, (UIntPtr)f.Length));
            return f;
        }

        public int JointIndex(string name) { int j; Error.Check(Native.cgamesh_model_joint_index(Handle, name, out j)); return j; }
        public int ClipIndex(string name) { int c; Error.Check(Native.cgamesh_model_clip_index(Handle, name, out c)); return c; }
        public double ClipDuration(int clip) { double s; Error.Check(Native.cgamesh_model_clip_duration(Handle, clip, out s)); return s; }

        /// <summary>Mesh `mesh` in `pose` (null: the bind pose), world space, into the caller's
        /// arrays (#V*3 each; normals may be null). Allocates nothing managed.</summary>
        public void Skin(Pose pose, int mesh, float[] positions, float[] normals = null, Skinning mode = Skinning.Cga)
        {
            Error.Check(Native.cgamesh_model_skin(Handle, pose == null ? PoseHandle.Null : pose.Handle, mesh, mode,
                                                  positions, (UIntPtr)(positions == null ? 0 : positions.Length),
                                                  normals, (UIntPtr)(normals == null ? 0 : normals.Length)));
        }

        /// <summary>Deformed by a spec given as JSON text (the CLI's `deform --spec`).</summary>
        public Model Deform(string specJson)
        {
            ModelHandle h;
            Error.Check(Native.cgamesh_model_deform(Handle, specJson, out h));
            return new Model(h);
        }

        public void Dispose() { Handle.Dispose(); }
    }

    /// <summary>A pose of a model's skeleton: the bind pose to begin with.</summary>
    public sealed class Pose : IDisposable
    {
        internal readonly PoseHandle Handle;
        private readonly Model model_;
        private readonly double[] vector_ = new double[3];

        public Pose(Model model)
        {
            model_ = model;
            Error.Check(Native.cgamesh_pose_create(model.Handle, out Handle));
        }

        /// <summary>Clip `clip` at `time` s (clip -1 with time &lt; 0: the bind pose), then the
        /// edits again. Past the clip's end: its last pose, and Warnings says so.</summary>
        public void Sample(int clip, double time, Blend blend = Blend.Format)
        {
            Error.Check(Native.cgamesh_pose_sample(Handle, model_.Handle, clip, time, blend));
        }

        public void Rotate(int joint, double axisX, double axisY, double axisZ, double degrees)
        {
            vector_[0] = axisX; vector_[1] = axisY; vector_[2] = axisZ;
            Error.Check(Native.cgamesh_pose_rotate(Handle, model_.Handle, joint, vector_, degrees));
        }

        public void Translate(int joint, double x, double y, double z)
        {
            vector_[0] = x; vector_[1] = y; vector_[2] = z;
            Error.Check(Native.cgamesh_pose_translate(Handle, model_.Handle, joint, vector_));
        }

        /// <summary>A dilator: uniform scale relative to the parent bone, &gt; 0.</summary>
        public void Scale(int joint, double scale) { Error.Check(Native.cgamesh_pose_scale(Handle, model_.Handle, joint, scale)); }

        public void SetMorphWeight(string target, float weight)
        {
            Error.Check(Native.cgamesh_pose_set_morph_weight(Handle, model_.Handle, target, weight));
        }

        public void ClearEdits() { Error.Check(Native.cgamesh_pose_clear_edits(Handle, model_.Handle)); }

        public string[] Warnings
        {
            get
            {
                UIntPtr n;
                Error.Check(Native.cgamesh_pose_warning_count(Handle, out n));
                var out_ = new string[(int)n];
                for (int i = 0; i < out_.Length; ++i)
                {
                    IntPtr text;
                    Error.Check(Native.cgamesh_pose_warning(Handle, (UIntPtr)i, out text));
                    out_[i] = Native.Text(text);
                }
                return out_;
            }
        }

        public void Dispose() { Handle.Dispose(); }
    }

    /// <summary>What one operation in place changed, per mesh.</summary>
    public sealed class Change : IDisposable
    {
        internal readonly ChangeHandle Handle;
        internal Change(ChangeHandle handle) { Handle = handle; }

        public int MeshCount { get { UIntPtr n; Error.Check(Native.cgamesh_change_mesh_count(Handle, out n)); return (int)n; } }
        public MeshChange Mesh(int index) { MeshChange c; Error.Check(Native.cgamesh_change_mesh(Handle, (UIntPtr)index, out c)); return c; }

        /// <summary>The operation's counts and warnings, as the CLI's --json.</summary>
        public string Json()
        {
            IntPtr json;
            Error.Check(Native.cgamesh_change_json(Handle, out json));
            return Native.Take(json);
        }

        public int[] NewFaces(int index)
        {
            var f = new int[Mesh(index).NewFaces];
            Error.Check(Native.cgamesh_change_new_faces(Handle, (UIntPtr)index, f, (UIntPtr)f.Length));
            return f;
        }

        public int[] NewFaceCorners(int index)
        {
            var c = new int[3 * Mesh(index).NewFaces];
            Error.Check(Native.cgamesh_change_new_face_corners(Handle, (UIntPtr)index, c, (UIntPtr)c.Length));
            return c;
        }

        /// <summary>(id before, id after) pairs.</summary>
        public int[] MovedFaces(int index)
        {
            var m = new int[2 * Mesh(index).MovedFaces];
            Error.Check(Native.cgamesh_change_moved_faces(Handle, (UIntPtr)index, m, (UIntPtr)m.Length));
            return m;
        }

        /// <summary>Per new vertex, up to 3 old vertices (-1: unused) and their weights.</summary>
        public void Origins(int index, out int[] vertices, out float[] weights)
        {
            int n = 3 * Mesh(index).NewVertices;
            vertices = new int[n];
            weights = new float[n];
            Error.Check(Native.cgamesh_change_origins(Handle, (UIntPtr)index, vertices, weights, (UIntPtr)n));
        }

        /// <summary>Brings a copy of the mesh's faces (#F*3 before the change) up to date:
        /// moved faces to their new slots, new faces into theirs.</summary>
        public int[] UpdateFaces(int index, int[] facesBefore)
        {
            MeshChange c = Mesh(index);
            int count = facesBefore.Length / 3 - c.RemovedFaces + c.NewFaces;
            var after = new int[3 * count];
            Array.Copy(facesBefore, after, Math.Min(facesBefore.Length, after.Length));
            int[] moved = MovedFaces(index);
            for (int i = 0; i < moved.Length; i += 2) Array.Copy(facesBefore, 3 * moved[i], after, 3 * moved[i + 1], 3);
            int[] ids = NewFaces(index), corners = NewFaceCorners(index);
            for (int i = 0; i < ids.Length; ++i) Array.Copy(corners, 3 * i, after, 3 * ids[i], 3);
            return after;
        }

        public void Dispose() { Handle.Dispose(); }
    }

    /// <summary>A model placed in a pose and cut, torn and drilled in place.</summary>
    public sealed class LiveModel : IDisposable
    {
        internal readonly LiveHandle Handle;
        private readonly double[] a_ = new double[3], b_ = new double[3];

        /// <summary>Copies `model` and places it in `pose` (null: the bind pose).</summary>
        public LiveModel(Model model, Pose pose = null)
        {
            Error.Check(Native.cgamesh_live_create(model.Handle, pose == null ? PoseHandle.Null : pose.Handle, out Handle));
        }

        /// <summary>The model as it is now (a copy).</summary>
        public Model Snapshot()
        {
            ModelHandle h;
            Error.Check(Native.cgamesh_live_model(Handle, out h));
            return new Model(h);
        }

        public int VertexCount(int mesh) { int v, f; Error.Check(Native.cgamesh_live_mesh_size(Handle, mesh, out v, out f)); return v; }
        public int FaceCount(int mesh) { int v, f; Error.Check(Native.cgamesh_live_mesh_size(Handle, mesh, out v, out f)); return f; }

        public int[] Faces(int mesh)
        {
            var f = new int[3 * FaceCount(mesh)];
            Error.Check(Native.cgamesh_live_mesh_faces(Handle, mesh, f, (UIntPtr)f.Length));
            return f;
        }

        /// <summary>As Model.Skin, on the model as it is now (with the tissue where it is simulated).</summary>
        public void Skin(Pose pose, int mesh, float[] positions, float[] normals = null, Skinning mode = Skinning.Cga)
        {
            Error.Check(Native.cgamesh_live_skin(Handle, pose == null ? PoseHandle.Null : pose.Handle, mesh, mode,
                                                 positions, (UIntPtr)(positions == null ? 0 : positions.Length),
                                                 normals, (UIntPtr)(normals == null ? 0 : normals.Length)));
        }

        /// <summary>Cuts by the plane n·x = d (placed coordinates).</summary>
        public Change Cut(double nx, double ny, double nz, double d)
        {
            a_[0] = nx; a_[1] = ny; a_[2] = nz;
            ChangeHandle h;
            Error.Check(Native.cgamesh_live_cut(Handle, a_, d, out h));
            return new Change(h);
        }

        /// <summary>Tears along the scalpel's path: blades holds 6 doubles per position (handle
        /// x y z, tip x y z), at least two.</summary>
        public Change Tear(double[] blades, double open = 0)
        {
            ChangeHandle h;
            Error.Check(Native.cgamesh_live_tear(Handle, blades, (UIntPtr)(blades == null ? 0 : blades.Length / 6), open, out h));
            return new Change(h);
        }

        public Change Drill(double tipX, double tipY, double tipZ, double baseX, double baseY, double baseZ, double radius,
                            bool wall = false)
        {
            a_[0] = tipX; a_[1] = tipY; a_[2] = tipZ;
            b_[0] = baseX; b_[1] = baseY; b_[2] = baseZ;
            ChangeHandle h;
            Error.Check(Native.cgamesh_live_drill(Handle, a_, b_, radius, wall ? 1 : 0, out h));
            return new Change(h);
        }

        /// <summary>Living tissue on (or its options changed): later operations open as the
        /// skin responds.</summary>
        public void SetTissue(TissueOptions options) { Error.Check(Native.cgamesh_live_set_tissue(Handle, ref options)); }
        public void ClearTissue() { Error.Check(Native.cgamesh_live_clear_tissue(Handle)); }
        public void StepTissue(Pose pose, double dt)
        {
            Error.Check(Native.cgamesh_live_step_tissue(Handle, pose == null ? PoseHandle.Null : pose.Handle, dt));
        }
        public void BakeTissue(Pose pose)
        {
            Error.Check(Native.cgamesh_live_bake_tissue(Handle, pose == null ? PoseHandle.Null : pose.Handle));
        }

        public void Dispose() { Handle.Dispose(); }
    }

    public static class Library
    {
        public static string Version { get { return Native.Text(Native.cgamesh_version()); } }
        /// <summary>Throws when the library loaded is not the one this file was written for.</summary>
        public static void CheckAbi()
        {
            int loaded = Native.cgamesh_abi_version();
            if (loaded != Native.AbiVersion)
                throw new CgameshException(Status.Internal, "libcgamesh_c has ABI " + loaded + ", Cgamesh.cs expects " + Native.AbiVersion);
        }
    }
}
