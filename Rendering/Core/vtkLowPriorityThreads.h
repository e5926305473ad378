// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
/**
 * @class   vtkLowPriorityThreads
 * @brief   parallel loops in threads of low priority, for work done while an application renders
 *
 * Work done in the background while an application renders (measuring and building a
 * pre-integration table after an edit) must not slow the rendering, which on a software
 * OpenGL such as Mesa's llvmpipe uses every core itself. vtkSMPTools' threads run at normal
 * priority and are shared with the rendering thread's own parallel work, so background loops
 * run here instead: For() starts one thread per core, each at low priority, which take chunks
 * of the range until it is done.
 *
 * Low priority is a nice value of 10 on Linux (setpriority of the thread): where a thread of
 * normal priority wants the core, such a thread gets about a tenth of it, so a frame drawn
 * meanwhile is barely slowed, and the work still goes on when other programs keep the cores
 * busy (an idle scheduling class would stop it then). Elsewhere the threads keep normal
 * priority. A thread's nice value cannot be lowered again without privileges, so only threads
 * made for background work are given it. Not wrapped.
 */
#ifndef vtkLowPriorityThreads_h
#define vtkLowPriorityThreads_h

#include "hovrRenderingCoreModule.h" // For export macro
#include "vtkType.h"                 // For vtkIdType

#include <functional> // For std::function

class HOVRRENDERINGCORE_EXPORT vtkLowPriorityThreads
{
public:
  /**
   * body(begin, end) over [0, n) in chunks of at most grain, in one thread of low priority per
   * core; the calling thread waits, and returns when every chunk is done. When no thread can
   * be started, the calling thread does it all.
   */
  static void For(vtkIdType n,
    vtkIdType grain,
    const std::function<void(vtkIdType, vtkIdType)>& body);

  /**
   * Give the calling thread low priority (for good: see the class description).
   */
  static void LowerPriority();
};

#endif
