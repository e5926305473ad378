// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkHovrVolumeRepresentation
 * @brief   ParaView's image volume representation drawn by hovr's mappers
 *
 * vtkImageVolumeRepresentation with its mapper (a vtkMultiBlockVolumeMapper in ParaView 5.11)
 * replaced by one of hovr's: vtkPreIntegrationVolumeMapper (stock, first- and second-order
 * pre-integration), vtkAnalyticVolumeMapper or vtkObjectOrderVolumeMapper, chosen by
 * Integration (the GUI's Rendering Method). The plugin offers it as the "hovr Volume"
 * representation of image data. What the superclass forwards to any vtkVolumeMapper and to
 * the vtkVolumeProperty (array selection, transfer functions, scalar opacity unit distance,
 * blend mode, cropping, interpolation) keeps working. Settings that only
 * vtkSmartVolumeMapper/vtkMultiBlockVolumeMapper know (volume rendering mode, global
 * illumination, the Y-axis array of a 2D transfer function) are skipped by the superclass for
 * another mapper type and have no effect. Partitioned datasets are not drawn (the superclass
 * warns); the mapper itself draws rectilinear grids, multi-component data, shaded second
 * order, shading under positional lights, blend modes other than composite and 2D transfer
 * functions with VTK's stock path. With Shade on, first order is lit as it is pre-integrated
 * (Guetat et al. 2010), as GradientInterpolation, Gooch and NormalArrayName say.
 *
 * Integration values beyond the pre-integration modes choose hovr's vtkAnalyticVolumeMapper
 * instead (ANALYTIC_ISOSURFACE, ANALYTIC_MIP, ANALYTIC_MINIP): the exact first hit of the
 * volume property's isosurface values (ParaView's "Isosurfaces" of the volume representation)
 * or the exact maximum or minimum along each ray; the blend mode follows the choice.
 * OBJECT_ORDER chooses hovr's vtkObjectOrderVolumeMapper: composite rendering on the CPU
 * (object-order ray casting, for servers without a GPU), in parallel projection; with a
 * perspective camera it draws with VTK's vtkFixedPointVolumeRayCastMapper after a warning.
 *
 * Under MPI (pvbatch or pvserver on several ranks) every rank draws its piece of the volume
 * and ParaView joins the images front to back ("over"). Every rank's mapper spans the whole
 * volume's scalar range and anchors its sampling to the whole volume's bounds (reduced over
 * the ranks when the data update: GetWholeScalarRange, GetWholeBounds), so that each piece is
 * drawn as the whole volume draws it. On several ranks the representation asks for ghost
 * points around each piece (two sample distances and two points deep), and pre-integration
 * draws each piece with them (vtkExtensibleGPUVolumeRayCastMapper::SetOwnedExtent: a segment or
 * slab that starts in a piece is drawn whole, as the whole volume draws it), and so does
 * object order (vtkObjectOrderRayCaster::SetOwnedExtent: a sample's step is drawn by the piece
 * that holds the sample) and the adaptive ray (2^(l_max + 1) sample distances and two points
 * deep: its walk joins the whole volume's on the slices every walk samples, and its oracle is
 * computed with them). The adaptive 3D method joins its walks likewise, 2^(l_max + 2) slice
 * spacings and two points deep; its slices are a pixel apart, so the depth is taken for the
 * camera at the data update, or for the one that shows the whole volume if that is larger, and
 * a camera zoomed out past both draws each piece as a volume of its own until the next update.
 * The analytic methods draw the piece without them. Pre-integration measures its table sizes on the
 * whole volume on every rank (put together from the pieces when the data update,
 * vtkWholeVolumeAssembler: every point up to 64 MiB of values, else every few points), so
 * that every rank draws the table one rank draws. A maximum or minimum over the
 * pieces is not joined
 * front to back: for ANALYTIC_MIP and ANALYTIC_MINIP the representation asks for no ordered
 * compositing and the mapper writes each pixel's depth from its extremum
 * (vtkAnalyticVolumeMapper::ExtremumDepth), so that ParaView's z-buffer compositing keeps the
 * rank that holds it. Beside a representation that needs ordered compositing they give a
 * warning (once, from rank 0, until that changes).
 *
 * The hovr settings below are kept here and passed to the mapper before every render
 * (UpdateMapperParameters), so changing one does not re-execute the representation.
 */
#ifndef vtkHovrVolumeRepresentation_h
#define vtkHovrVolumeRepresentation_h

#include "hovrParaViewRepresentationModule.h" // For export macro
#include "vtkImageData.h"                     // For the sizing volume (vtkSmartPointer)
#include "vtkImageVolumeRepresentation.h"
#include "vtkSmartPointer.h" // For ivars

class vtkAlgorithm;

class vtkAdaptiveSamplingOracle;
class vtkVolumeMapper;

class HOVRPARAVIEWREPRESENTATION_EXPORT vtkHovrVolumeRepresentation
  : public vtkImageVolumeRepresentation
{
public:
  static vtkHovrVolumeRepresentation* New();
  vtkTypeMacro(vtkHovrVolumeRepresentation, vtkImageVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Integration values after vtkPreIntegrationVolumeMapper::IntegrationModes (0-2): the
   * analytic methods of vtkAnalyticVolumeMapper.
   */
  enum AnalyticModes
  {
    ANALYTIC_ISOSURFACE = 3,
    ANALYTIC_MIP = 4,
    ANALYTIC_MINIP = 5,
    OBJECT_ORDER = 6,
    ADAPTIVE_RAY = 7, ///< vtkAdaptiveRayVolumeMapper: adaptive sampling along each ray
    ADAPTIVE_3D = 8   ///< vtkAdaptiveSamplingVolumeMapper: the slice pyramid (parallel only)
  };

  ///@{
  /**
   * How samples are composited: a value of vtkPreIntegrationVolumeMapper::IntegrationModes,
   * passed on unchanged (the mapper validates it), or one of AnalyticModes, which draw with
   * vtkAnalyticVolumeMapper. Initial value is the pre-integration mapper's, FIRST_ORDER.
   */
  virtual void SetIntegration(int integration);
  vtkGetMacro(Integration, int);
  ///@}

  ///@{
  /**
   * Distance between samples along a ray, in world units; 0 (or any value that is not
   * positive) chooses half the smallest grid spacing of the input (the mean spacing of a
   * rectilinear grid), i.e. two samples per cell along its shortest edge. On several ranks a
   * change asks for the ghost points it needs (see RequestUpdateExtent). Initial value is 0.
   */
  virtual void SetSampleDistance(double distance);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * Entries of the pre-integration table along each scalar axis; 0 lets the mapper choose
   * (see vtkPreIntegrationVolumeMapper::SetTableSize). Initial value is the mapper's, 0.
   */
  vtkSetMacro(TableSize, int);
  vtkGetMacro(TableSize, int);
  ///@}

  ///@{
  /**
   * The largest table the measured sizes consider, in bytes (see
   * vtkPreIntegrationVolumeMapper::SetTableMemoryLimit). Initial value is the mapper's, 64 MiB.
   */
  vtkSetMacro(TableMemoryLimit, double);
  vtkGetMacro(TableMemoryLimit, double);
  ///@}

  ///@{
  /**
   * Storage of the table on the GPU: a value of
   * vtkPreIntegrationVolumeMapper::TablePrecisions, passed on unchanged (the mapper clamps it).
   * Initial value is the mapper's, PRECISION_AUTOMATIC.
   */
  vtkSetMacro(TablePrecision, int);
  vtkGetMacro(TablePrecision, int);
  ///@}

  ///@{
  /**
   * The most integration steps per entry of the table (see
   * vtkPreIntegrationVolumeMapper::SetIterations), clamped to [1, 4096].
   * Initial value is the mapper's, 64.
   */
  vtkSetClampMacro(Iterations, int, 1, 4096);
  vtkGetMacro(Iterations, int);
  ///@}

  ///@{
  /**
   * Box-average the transfer function over one entry spacing of the table's centre axis: a
   * value of vtkPreIntegrationVolumeMapper::TablePrefilters, passed on unchanged (the mapper
   * clamps it). Initial value is the mapper's, PREFILTER_AUTOMATIC.
   */
  vtkSetMacro(TablePrefilter, int);
  vtkGetMacro(TablePrefilter, int);
  ///@}

  ///@{
  /**
   * How the volume is uploaded: a value of vtkPreIntegrationVolumeMapper::VolumePrecisions,
   * passed on unchanged (the mapper clamps it). Initial value is the mapper's,
   * VOLUME_PRECISION_AUTOMATIC.
   */
  vtkSetMacro(VolumePrecision, int);
  vtkGetMacro(VolumePrecision, int);
  ///@}

  ///@{
  /**
   * Shaded first-order pre-integration (the volume property's Shade on, Integration
   * FIRST_ORDER), passed on unchanged to vtkPreIntegrationVolumeMapper, which documents them:
   * GradientInterpolation, how the normal varies along a segment (a value of
   * vtkVolumeShadingModel::GradientInterpolations, which the mapper clamps; initial value
   * NONLINEAR), and Gooch, Gooch shading instead of Blinn-Phong (initial value false). The
   * initial values are the mapper's.
   */
  vtkSetMacro(GradientInterpolation, int);
  vtkGetMacro(GradientInterpolation, int);
  vtkSetMacro(Gooch, bool);
  vtkGetMacro(Gooch, bool);
  vtkBooleanMacro(Gooch, bool);
  ///@}

  ///@{
  /**
   * The point array of 3-component vectors that shaded first-order pre-integration takes as
   * its normals (see vtkPreIntegrationVolumeMapper::SetNormalArrayName). nullptr, an empty
   * name or "None" (the GUI's entry for no array) choose VTK's central-difference gradient of
   * the scalars. A name the input lacks is the mapper's error: nothing is drawn. Initial
   * value is nullptr.
   */
  vtkSetStringMacro(NormalArrayName);
  vtkGetStringMacro(NormalArrayName);
  ///@}

  ///@{
  /**
   * Settings of the object-order CPU ray caster (OBJECT_ORDER), passed on unchanged to its
   * vtkObjectOrderRayCaster, which documents and clamps them: ObjectOrderClassification
   * (vtkObjectOrderRayCaster::Classifications, initial value PREINTEGRATED),
   * ObjectOrderShading (ShadingModes, used when Shade is on; initial value POST_SHADING),
   * InterleavedSampling (initial value true), HiddenVolumeRemoval (initial value true; the
   * image is the same either way), OpacityThreshold (early ray termination, initial value
   * 0.996), LeafSize (cells per edge of the octree's leaves, initial value 8) and
   * InstructionSet (the compiled copy of the sample loop, InstructionSets, initial value
   * INSTRUCTIONS_AUTOMATIC). The initial values are the caster's own.
   */
  vtkSetMacro(ObjectOrderClassification, int);
  vtkGetMacro(ObjectOrderClassification, int);
  vtkSetMacro(ObjectOrderShading, int);
  vtkGetMacro(ObjectOrderShading, int);
  vtkSetMacro(InterleavedSampling, bool);
  vtkGetMacro(InterleavedSampling, bool);
  vtkSetMacro(HiddenVolumeRemoval, bool);
  vtkGetMacro(HiddenVolumeRemoval, bool);
  vtkSetMacro(OpacityThreshold, double);
  vtkGetMacro(OpacityThreshold, double);
  vtkSetMacro(LeafSize, int);
  vtkGetMacro(LeafSize, int);
  vtkSetMacro(InstructionSet, int);
  vtkGetMacro(InstructionSet, int);
  ///@}

  ///@{
  /**
   * Adaptive sampling (ADAPTIVE_RAY, ADAPTIVE_3D): the oracle volume is computed from the
   * input and the opacity map by a vtkAdaptiveSamplingOracle inside the representation
   * (again when the opacity map changes). MaximumLevel is l_max (sampling distances up to
   * 2^l_max base steps; initial value 3, the paper's), OracleMode a value of
   * vtkAdaptiveSamplingOracle::Modes (initial value OPACITY_RANGE; MIN samples at the full
   * rate) and OracleEpsilon its feature threshold (initial value 0.002). The mappers and the
   * filter validate them. On several ranks a new MaximumLevel asks for the ghost points the
   * adaptive ray then reads.
   */
  virtual void SetMaximumLevel(int level);
  vtkGetMacro(MaximumLevel, int);
  vtkSetMacro(OracleMode, int);
  vtkGetMacro(OracleMode, int);
  vtkSetMacro(OracleEpsilon, double);
  vtkGetMacro(OracleEpsilon, double);
  ///@}

  ///@{
  /**
   * Blend mode and cropping flag, kept here and given to whichever mapper draws (the
   * superclass sets them on its current mapper only). The analytic modes override the blend
   * mode with theirs. Initial values: composite, off.
   */
  void SetBlendMode(int blend);
  void SetCropping(int crop);
  ///@}

  /**
   * The sample distance the mapper was last given: SampleDistance, or the automatic value
   * derived from the input when SampleDistance is not positive. 0 before the first render.
   */
  vtkGetMacro(EffectiveSampleDistance, double);

  ///@{
  /**
   * Draw each change at once and refine in the background: pre-integration with interim table
   * sizes while the table is measured (vtkPreIntegrationVolumeMapper::SetRefineInBackground),
   * adaptive sampling with the last oracle distances while the new ones are computed
   * (vtkAdaptiveSamplingOracle::SetRefineInBackground). The GUI turns it on, and re-renders
   * when the refined table or oracle is ready (GetRefinementState). Ignored by pvbatch, whose
   * frames always wait for them. Initial value is false.
   */
  vtkSetMacro(RefineInBackground, bool);
  vtkGetMacro(RefineInBackground, bool);
  ///@}

  enum RefinementStates
  {
    REFINEMENT_NONE = 0,    ///< the table drawn is the measured one (or none is measured)
    REFINEMENT_RUNNING = 1, ///< interim sizes drawn, the measurement runs
    REFINEMENT_READY = 2    ///< the measured table waits for the next render
  };

  /**
   * Where the background measurement of the current mapper (or its oracle) stands
   * (RefinementStates).
   */
  int GetRefinementState();

  /**
   * How far the background measurement is, in [0, 1] (1 when none runs).
   */
  double GetRefinementProgress();

  /**
   * Background measurements the pre-integration mapper has completed since it was made (its
   * refiner's count; 0 for the other methods): a client can tell that an edit was refined in
   * the background even when the measurement ended before it asked for the state.
   */
  int GetRefinementCount();

  /**
   * The range of the coloured array's first component (its finite values) over every rank's
   * piece of the data, which the mappers' tables, textures and classification span on every
   * rank, so that each rank draws its piece as one rank draws the whole volume. Empty
   * (low > high) before the first update or without such an array.
   */
  vtkGetVector2Macro(WholeScalarRange, double);

  /**
   * The bounds of every rank's piece together (the whole volume's), which the mappers anchor
   * their sampling grids to on every rank. Empty (a minimum above its maximum) before the
   * first update or without data.
   */
  vtkGetVector6Macro(WholeBounds, double);

  /**
   * On several ranks, the volume pre-integration measures its table sizes on
   * (vtkPreIntegrationVolumeMapper::SetSizingVolume): the whole volume's coloured point array
   * at a stride (1 while its values take at most 64 MiB, 256^3 float values; beyond, every
   * second, third ... point along each axis), put together from every rank's piece when the
   * data update, for the pre-integration methods. nullptr on one rank (the input is the whole
   * volume), for the other methods, on a rank without data, or for cell or multi-component
   * arrays.
   */
  vtkImageData* GetSizingVolume() { return this->SizingVolume; }

  /**
   * The entries along the centre, chord and deviation axes of the pre-integration table drawn
   * last (0, 0, 0 for the methods without one).
   */
  int* GetTableSizes() VTK_SIZEHINT(3);

protected:
  vtkHovrVolumeRepresentation();
  ~vtkHovrVolumeRepresentation() override;

  // The superclass's, then the whole range and bounds over the ranks (a collective call: every
  // rank of the data server runs it).
  // The superclass's, and on several ranks ghost points around the piece (GhostLevels()).
  int RequestUpdateExtent(vtkInformation* request,
    vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  // Ghost points pre-integration reads past a piece at SampleDistance (or the automatic one)
  // on a grid of the given smallest spacing: two sample distances and two points.
  int GhostLevels(double spacing);

  int RequestData(vtkInformation* request,
    vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  void UpdateMapperParameters() override;

  // The superclass's; for Analytic MIP and MinIP on several ranks, no ordered compositing (the
  // mapper writes each pixel's depth from its extremum, so that IceT's z-buffer compositing
  // keeps the pixel of the rank that holds the extremum).
  int ProcessViewRequest(vtkInformationRequestKey* request_type,
    vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  // Whether this process is one of several ranks and the method a projection.
  bool DistributedProjection();

  // On several ranks, the whole volume from every rank's piece of the coloured array (a
  // collective call, in RequestData): SizingVolume, assembled again when any rank's data
  // changed.
  void AssembleSizingVolume(vtkInformation* inInfo, vtkDataObject* input, vtkDataArray* scalars);

  // Half the smallest grid spacing of the mapper's input, or 0 when there is no grid.
  double ComputeAutomaticSampleDistance();

  // The mappers; VolumeMapper points to the one the Integration value chooses.
  vtkSmartPointer<vtkVolumeMapper> PreIntegrationMapper;
  vtkSmartPointer<vtkVolumeMapper> AnalyticMapper;
  vtkSmartPointer<vtkVolumeMapper> ObjectOrderMapper;
  vtkSmartPointer<vtkVolumeMapper> AdaptiveRayMapper;
  vtkSmartPointer<vtkVolumeMapper> AdaptivePyramidMapper;
  // Between the data and the adaptive mappers: the oracle volume.
  vtkSmartPointer<vtkAdaptiveSamplingOracle> Oracle;

  // The mapper's settings start from the mapper's own defaults (set in the constructor).
  int Integration;
  int BlendMode = 0;
  int Cropping = 0;
  double SampleDistance = 0.0;
  int TableSize;
  double TableMemoryLimit;
  int TablePrecision;
  int Iterations;
  int TablePrefilter;
  int VolumePrecision;
  int GradientInterpolation;
  bool Gooch;
  char* NormalArrayName = nullptr;
  int ObjectOrderClassification;
  int ObjectOrderShading;
  bool InterleavedSampling;
  bool HiddenVolumeRemoval;
  double OpacityThreshold;
  int LeafSize;
  int InstructionSet;
  int MaximumLevel;
  int OracleMode;
  double OracleEpsilon;
  double EffectiveSampleDistance = 0.0;
  bool WarnedDistributedProjection = false;
  bool OrderedCompositingInView = false; // the view composites in order (another needs it)
  bool RefineInBackground = false;
  double WholeScalarRange[2] = { 1.0, 0.0 };
  vtkSmartPointer<vtkImageData> SizingVolume;
  // On several ranks: the points of the piece without its ghost points (empty: none), and the
  // piece without them for the methods that do not read ghost points.
  int OwnedExtent[6] = { 0, -1, 0, -1, 0, -1 };
  int GhostWidth = 0; // the fewest ghost points past an owned face that has a neighbour
  // The slice pyramid's slice spacing for its ghost points (world; 0: not known yet).
  double PyramidSliceSpacing = 0.0;
  vtkSmartPointer<vtkAlgorithm> Cropper;
  int TableSizes[3] = { 0, 0, 0 };
  // What SizingVolume was assembled from on this rank: the array and its modification time.
  vtkDataArray* SizingSource = nullptr;
  vtkMTimeType SizingSourceTime = 0;
  double WholeBounds[6] = { 1.0, 0.0, 1.0, 0.0, 1.0, 0.0 };

private:
  vtkHovrVolumeRepresentation(const vtkHovrVolumeRepresentation&) = delete;
  void operator=(const vtkHovrVolumeRepresentation&) = delete;
};

#endif
